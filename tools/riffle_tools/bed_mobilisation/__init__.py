"""What mobilises the bed in the sloshing tank: sloshing against pore-water locking in a coupled run, the bed's
horizontal load budget, the load above each depth, the wall gauges, and a linear long-wave model (README.md here).

The tank's motion is riffle's (riffle_tools.tank_motion), the seed experiment's by default.
"""
from ..tank_motion import SEED_AMPLITUDE, SEED_FREQUENCY, SEED_RAMP_TIME, SinusoidalMotion


def add_motion_arguments(parser):
    """--amplitude, --frequency, --ramp-time of the tank (default: the seed experiment's)."""
    parser.add_argument("--amplitude", type=float, default=SEED_AMPLITUDE, help="A [m] (default %(default)g)")
    parser.add_argument("--frequency", type=float, default=SEED_FREQUENCY, help="f [Hz] (default %(default)g)")
    parser.add_argument("--ramp-time", type=float, default=SEED_RAMP_TIME, help="[s] (default %(default)g)")


def motion_of(args):
    return SinusoidalMotion(args.amplitude, args.frequency, args.ramp_time)
