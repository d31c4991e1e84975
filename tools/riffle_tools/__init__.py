"""riffle's Python tools: figures, studies and checks on riffle's outputs, one module per command.

Run them through the launcher, tools/riffle-tools COMMAND ... (tools/riffle-tools --help lists them), or as
/usr/bin/python3 -m riffle_tools.MODULE ... from tools/. Shared modules: vtp (ParaView frames), run_outputs (riffle's
CSV outputs), tank_motion (the tank's sinusoidal motion with its start-up ramp), plotting (headless matplotlib),
study_jobs (a study's definition and job records, for study and study_collect).
"""
import pathlib
import sys

PACKAGE = pathlib.Path(__file__).resolve().parent
TOOLS = PACKAGE.parent
ROOT = TOOLS.parent
LAUNCHER = TOOLS / "riffle-tools"


def command(name, *args):
    """The argv that runs another tool in a fresh interpreter: [python, tools/riffle-tools, name, args...]."""
    return [sys.executable, str(LAUNCHER), name, *[str(a) for a in args]]
