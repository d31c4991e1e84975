"""Compare the MPS water (or the grains) of two runs frame by frame, particle by particle (matched by id): the largest
differences of position, velocity and pressure (grains: the drag force instead), against bounds given on the command
line. Exit 1 if any frame exceeds one or a frame is missing or holds other particles.

  compare_fluid_frames.py RUN_A RUN_B FRAME... [--grains] [--position M] [--velocity FRACTION] [--pressure FRACTION]

--position is in metres; --velocity and --pressure are fractions of the frame's largest |u| and |p| (grains: |drag|)
in RUN_A.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import numpy as np  # noqa: E402
from riffle_tools.vtp import read_vtp  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("a")
parser.add_argument("b")
parser.add_argument("frames", nargs="+", type=int)
parser.add_argument("--position", type=float, default=1e-8)
parser.add_argument("--velocity", type=float, default=1e-6)
parser.add_argument("--pressure", type=float, default=1e-5)
parser.add_argument("--grains", action="store_true", help="compare solids_*.vtp (the drag force for the pressure)")
args = parser.parse_args()


def frame_path(run, name):
    """The frame's .vtp, or the .pvtp naming its pieces where the run wrote it over ranks in pieces (read_vtp joins
    them)."""
    path = os.path.join(run, "vtk", name)
    pieces = path[: -len(".vtp")] + ".pvtp"
    return pieces if os.path.exists(pieces) else path


ok = True
for frame in args.frames:
    name = f"{'solids' if args.grains else 'fluid'}_{frame:06d}.vtp"
    paths = [frame_path(run, name) for run in (args.a, args.b)]
    if not all(os.path.exists(p) for p in paths):
        print(f"{name}: missing in {' or '.join(p for p in paths if not os.path.exists(p))}")
        ok = False
        continue
    a, b = read_vtp(paths[0]), read_vtp(paths[1])
    ia, ib = np.argsort(a["id"]), np.argsort(b["id"])
    if len(ia) != len(ib) or not (a["id"][ia] == b["id"][ib]).all():
        print(f"{name}: other particles ({len(ia)} against {len(ib)})")
        ok = False
        continue
    position = np.abs(a["points"][ia] - b["points"][ib]).max()
    speed = max(np.abs(a["velocity"]).max(), 1e-300)
    velocity = np.abs(a["velocity"][ia] - b["velocity"][ib]).max() / speed
    field = "drag_force" if args.grains else "pressure"
    largest = max(np.abs(a[field]).max(), 1e-300)
    pressure = np.abs(a[field][ia] - b[field][ib]).max() / largest
    within = position <= args.position and velocity <= args.velocity and pressure <= args.pressure
    ok = ok and within
    print(f"{args.a} against {args.b}, {name} ({len(ia)} particles): position {position:.3g} m, velocity "
          f"{velocity:.3g} of the largest, {field.replace('_', ' ')} {pressure:.3g} of the largest{'' if within else ': TOO FAR'}")
sys.exit(0 if ok else 1)
