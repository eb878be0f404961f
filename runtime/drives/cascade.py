"""The DC axis cascade as one bank of axes: position P → velocity PI → current controller
with armature → power stage (averaged or PWM). One call advances every DC axis one step.

Start: at rest with the current (and PI integral, controller output) that holds the
given motor torque, so a run does not begin with the arm sagging.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime.drives import motor, power_stage
from irlc.runtime.drives.current import CurrentLoop
from irlc.runtime.drives.params import DcDrives
from irlc.runtime.drives.position import position_p
from irlc.runtime.drives.velocity import VelocityPI


class DcBank:
    def __init__(self, c: DcDrives, h: float, pwm: bool, holding_torque: np.ndarray):
        self.c, self.h, self.pwm = c, h, pwm
        i0 = np.clip(holding_torque / c.ks, -c.i_max, c.i_max)
        self.pi = VelocityPI(c.ke, c.kp, c.ki, c.u_ref_max, len(i0))
        self.pi.x = np.clip(c.k * i0, -c.u_ref_max, c.u_ref_max) / c.ki
        if pwm:
            self.stage = power_stage.PwmStage(
                c.R, c.L, c.ks, c.k, c.kiwzm, c.U, c.i_max, c.pwm_frequency
            )
            self.stage.i, self.stage.u_c = i0.copy(), c.R * i0
        else:
            self.loop = CurrentLoop(c.R, c.L, c.ks, c.k, c.kiwzm, h)
            self.loop.x[:, 0], self.loop.x[:, 1] = i0, c.R * i0

    def step(self, theta_ref, theta, omega, t: float):
        """Motor torque, mean current, mean voltage, saturation flags, electrical energy in
        and copper loss over the step."""
        c = self.c
        u_w, sat_p = position_p(c.kz, theta_ref, theta, c.u_ref_max)
        u_i, sat_v = self.pi.step(u_w, omega, self.h)
        if self.pwm:
            i_mean, u_mean, energy, copper, sat_s = self.stage.period(u_i, omega)
        else:
            i_mean, u_mean, energy, copper, sat_s = power_stage.averaged(
                self.loop, u_i, omega, c, self.h
            )
        return motor.torque(c.ks, i_mean), i_mean, u_mean, sat_p | sat_v | sat_s, energy, copper
