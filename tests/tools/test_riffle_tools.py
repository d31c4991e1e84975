#!/usr/bin/python3
"""Self-test of the tools' package and launcher (tools/riffle-tools, tools/riffle_tools/):

- `tools/riffle-tools --help` lists every command module of the package (each module with a main() is a command,
  apart from the launcher's own) and nothing that is not one; every command answers --help with exit 0, through
  the launcher and as `python3 -m riffle_tools.MODULE` from tools/; an unknown command exits 2;
- tools/README.md names every command and every shell script in tools/;
- the shared tank motion (riffle_tools.tank_motion): its array and scalar forms agree, the ramp is C2 (value, rate
  and curvature continuous at both ends), velocity and acceleration are the derivatives of the displacement, and
  the tank rests before start_time.

Usage: /usr/bin/python3 tests/tools/test_riffle_tools.py   (exit 0 = pass)
"""
import ast
import math
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOOLS = ROOT / "tools"
RIFFLE_TOOLS = [sys.executable, str(TOOLS / "riffle-tools")]
sys.path.insert(0, str(TOOLS))
import numpy as np  # noqa: E402
from riffle_tools import cli  # noqa: E402
from riffle_tools.tank_motion import SinusoidalMotion, start_up_ramp  # noqa: E402

failures = []


def check(condition, text):
    print(("ok - " if condition else "FAIL - ") + text)
    if not condition:
        failures.append(text)


def command_modules():
    """Every module of the package that defines main(), as a dotted name below riffle_tools."""
    found = []
    for path in sorted((TOOLS / "riffle_tools").rglob("*.py")):
        tree = ast.parse(path.read_text())
        if any(isinstance(node, ast.FunctionDef) and node.name == "main" for node in tree.body):
            found.append(".".join(path.relative_to(TOOLS / "riffle_tools").with_suffix("").parts))
    return [m for m in found if m not in ("cli", "__main__")]


def check_launcher():
    index = subprocess.run([*RIFFLE_TOOLS, "--help"], capture_output=True, text=True)
    check(index.returncode == 0, "riffle-tools --help exits 0")
    listed = {line.split()[0] for line in index.stdout.splitlines() if line.startswith("  ")}
    modules = {module: name for name, module, _ in cli.COMMANDS}
    for module in command_modules():
        check(module in modules and modules[module] in listed, f"--help lists the module {module}")
    check(listed == set(modules.values()), "--help lists only the commands of the package")
    check(all(line.strip() for line in index.stdout.splitlines()[4:]), "--help gives one line per command")
    for name, module, _ in cli.COMMANDS:
        through = subprocess.run([*RIFFLE_TOOLS, name, "--help"], capture_output=True, text=True)
        check(through.returncode == 0 and "usage: riffle-tools " + name in through.stdout,
              f"riffle-tools {name} --help exits 0 with its usage")
        direct = subprocess.run([sys.executable, "-m", "riffle_tools." + module, "--help"], capture_output=True,
                                text=True, cwd=TOOLS)
        check(direct.returncode == 0 and "usage:" in direct.stdout, f"python3 -m riffle_tools.{module} --help")
    unknown = subprocess.run([*RIFFLE_TOOLS, "no-such-command"], capture_output=True, text=True)
    check(unknown.returncode == 2 and "no-such-command" in unknown.stderr, "an unknown command exits 2, named")


def check_readme():
    readme = (TOOLS / "README.md").read_text()
    for name, _, _ in cli.COMMANDS:
        check(f"riffle-tools {name}" in readme, f"tools/README.md names {name}")
    for script in sorted(TOOLS.glob("*.sh")):
        check(f"tools/{script.name}" in readme, f"tools/README.md names tools/{script.name}")


def check_tank_motion():
    motion = SinusoidalMotion(0.01, 1.7, 0.5882, math.radians(20.0), 0.1)
    times = np.linspace(0.0, 2.0, 4001)
    scalar = np.array([motion.at(t) for t in times])
    arrays = np.column_stack([motion.displacement(times), motion.velocity(times), motion.acceleration(times)])
    check(np.allclose(scalar, arrays, rtol=0, atol=1e-15), "array and scalar kinematics agree")
    check(np.all(scalar[times < 0.1] [:, 1:] == 0) and np.all(scalar[times < 0.1][:, 0] == 0),
          "the tank rests before start_time (no ramp yet: x = 0)")
    h = 1e-6
    inside = times[(times > 0.1 + 1e-3)]
    dx = np.array([(motion.at(t + h)[0] - motion.at(t - h)[0]) / (2 * h) for t in inside])
    dv = np.array([(motion.at(t + h)[1] - motion.at(t - h)[1]) / (2 * h) for t in inside])
    check(np.max(np.abs(dx - motion.velocity(inside))) < 1e-6, "velocity = d(displacement)/dt")
    check(np.max(np.abs(dv - motion.acceleration(inside))) < 1e-4, "acceleration = d(velocity)/dt")
    for edge, expected in ((0.0, (0.0, 0.0, 0.0)), (1.0, (1.0, 0.0, 0.0))):
        got = start_up_ramp(edge * 2.0 + (1e-9 if edge == 0 else -1e-9), 2.0)
        check(all(abs(g - e) < 1e-6 for g, e in zip(got, expected)), f"ramp continuous (C2) at s = {edge:g}")
    check(start_up_ramp(1.0, 2.0) == (0.5, 30.0 * 0.25 * 0.25 / 2.0, 0.0), "ramp at s = 1/2: r = 1/2, r'' = 0")
    check(start_up_ramp(5.0, 0.0) == (1.0, 0.0, 0.0), "no ramp when ramp_time = 0")


check_launcher()
check_readme()
check_tank_motion()
print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
