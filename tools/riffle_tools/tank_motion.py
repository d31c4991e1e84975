"""The tank's sinusoidal motion exactly as riffle moves it (systems/physics/tank_kinematics.cpp):

    x(t) = -A r(tau) sin(2 pi f tau + phase),   tau = t - start_time (the tank rests before start_time),

r the C2 quintic start-up ramp over ramp_time, r(s) = s^3 (10 - 15 s + 6 s^2), s = tau / ramp_time (1 after it, and
throughout when ramp_time is 0). Velocity and acceleration are the derivatives, zero before start_time.

    from riffle_tools.tank_motion import SinusoidalMotion
    motion = SinusoidalMotion(amplitude=0.01, frequency=1.7, ramp_time=0.5882)
    x, v, a = motion.at(0.3)                     # floats (math, as the engine computes them)
    v = motion.velocity(times)                   # numpy arrays for numpy input
    motion = SinusoidalMotion.from_scene(scene)  # a scene's [tank.motion] table (tomllib's dict)

Scalars go through math.sin (bit for bit the engine's formula and order); arrays through numpy.
"""
import math

import numpy as np

# The seed experiment's motion (scenes/oscillating_tank.toml): A = 10 mm, f = 1.7 Hz, ramp over one period.
SEED_AMPLITUDE = 0.01
SEED_FREQUENCY = 1.7
SEED_RAMP_TIME = 0.5882


def start_up_ramp(time, ramp_time):
    """(r, r', r'') of the quintic start-up ramp at one time tau [s] since the motion's start."""
    if ramp_time <= 0.0 or time >= ramp_time:
        return 1.0, 0.0, 0.0
    if time <= 0.0:
        return 0.0, 0.0, 0.0
    s = time / ramp_time
    value = s * s * s * (10.0 + s * (-15.0 + 6.0 * s))
    rate = 30.0 * s * s * (1.0 - s) * (1.0 - s) / ramp_time
    curvature = 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / (ramp_time * ramp_time)
    return value, rate, curvature


def start_up_ramp_array(time, ramp_time):
    """start_up_ramp over a numpy array of times: (r, r', r'') arrays."""
    t = np.asarray(time, dtype=float)
    if ramp_time <= 0.0:
        return np.ones_like(t), np.zeros_like(t), np.zeros_like(t)
    s = np.clip(t / ramp_time, 0.0, 1.0)
    inside = (t > 0.0) & (t < ramp_time)
    value = np.where(t >= ramp_time, 1.0, np.where(t <= 0.0, 0.0, s * s * s * (10.0 + s * (-15.0 + 6.0 * s))))
    rate = np.where(inside, 30.0 * s * s * (1.0 - s) * (1.0 - s) / ramp_time, 0.0)
    curvature = np.where(inside, 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / (ramp_time * ramp_time), 0.0)
    return value, rate, curvature


class SinusoidalMotion:
    """[tank.motion] kind = "sinusoidal": amplitude A [m], frequency f [Hz], ramp_time [s], phase [rad],
    start_time [s]; displacement, velocity and acceleration along the motion's direction."""

    def __init__(self, amplitude, frequency, ramp_time=0.0, phase=0.0, start_time=0.0):
        self.amplitude = float(amplitude)
        self.frequency = float(frequency)
        self.ramp_time = float(ramp_time)
        self.phase = float(phase)
        self.start_time = float(start_time)
        self.omega = 2.0 * 3.14159265358979323846 * self.frequency

    @classmethod
    def from_scene(cls, scene):
        """From a scene read with tomllib (phase in degrees there, as riffle reads it)."""
        motion = scene.get("tank", {}).get("motion", {})
        return cls(motion.get("amplitude", 0.0), motion.get("frequency", 0.0), motion.get("ramp_time", 0.0),
                   math.radians(motion.get("phase", 0.0)), motion.get("start_time", 0.0))

    def at(self, time):
        """(x, v, a) at one time [s], as floats."""
        resting = time < self.start_time
        tau = 0.0 if resting else time - self.start_time
        sine = math.sin(self.omega * tau + self.phase)
        cosine = math.cos(self.omega * tau + self.phase)
        r, dr, ddr = start_up_ramp(tau, self.ramp_time)
        # x = -A r sin(wt); x' = -A (r' sin + r w cos); x'' = -A (r'' sin + 2 r' w cos - r w^2 sin)
        x = -self.amplitude * r * sine
        if resting:
            return x, 0.0, 0.0
        v = -self.amplitude * (dr * sine + r * self.omega * cosine)
        a = -self.amplitude * (ddr * sine + 2.0 * dr * self.omega * cosine - r * self.omega * self.omega * sine)
        return x, v, a

    def _arrays(self, times):
        t = np.asarray(times, dtype=float)
        resting = t < self.start_time
        tau = np.where(resting, 0.0, t - self.start_time)
        angle = self.omega * tau + self.phase
        return resting, np.sin(angle), np.cos(angle), start_up_ramp_array(tau, self.ramp_time)

    def displacement(self, times):
        """x [m] at each time (numpy)."""
        _, sine, _, (r, _, _) = self._arrays(times)
        return -self.amplitude * r * sine

    def velocity(self, times):
        """x' [m/s] at each time (numpy)."""
        resting, sine, cosine, (r, dr, _) = self._arrays(times)
        return np.where(resting, 0.0, -self.amplitude * (dr * sine + r * self.omega * cosine))

    def acceleration(self, times):
        """x'' [m/s^2] at each time (numpy)."""
        resting, sine, cosine, (r, dr, ddr) = self._arrays(times)
        w = self.omega
        return np.where(resting, 0.0, -self.amplitude * (ddr * sine + 2.0 * dr * w * cosine - r * w * w * sine))
