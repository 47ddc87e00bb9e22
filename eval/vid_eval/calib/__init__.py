"""Calibration tools for a user's own vehicle (docs/own-vehicle.md): ``vid-fit-thrust``
(rotor thrust coefficients from a hover / vertical-step log) and ``vid-allan`` (IMU noise
densities and random walks from a static log, in Kalibr's imu.yaml keys)."""
