"""matplotlib for the tools: headless (Agg), with a clear message where Debian's packages are missing.

    from riffle_tools import plotting
    plt = plotting.pyplot("plot_bed")   # exits with a message naming the tool if matplotlib is missing
"""
import sys


def pyplot(tool):
    """matplotlib.pyplot on the Agg backend; exits naming `tool` and the missing package when it cannot."""
    try:
        import numpy  # noqa: F401  (matplotlib needs it; say so clearly if it is missing)
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as error:  # pragma: no cover - depends on the machine
        sys.exit(f"{tool}: {error.name} is missing; install python3-numpy and python3-matplotlib (tools/setup.sh "
                 "does) and run it with /usr/bin/python3")
    return plt


def write(figure, path, tool, dpi=110):
    """Saves `figure` to `path` and says so as `<tool>: wrote <path>`."""
    figure.savefig(path, dpi=dpi)
    print(f"{tool}: wrote {path}")
