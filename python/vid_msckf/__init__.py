"""VID-MSCKF from Python: the C++ estimator (``vid_system::System``) with numpy in and out.

Run a dataset folder exactly as ``vid_run`` does (same output files; returns summary.json)::

    import vid_msckf
    summary = vid_msckf.run_dataset("seq", "out", config="config/sim")
    print(summary["ate_posyaw_m"], summary["force_rmse_world_mps2"])

or push samples yourself, in time order, and read the state back::

    sys = vid_msckf.System(dataset="seq")           # calibration from the dataset folder
    sys.push_imu(t_ns, gyro_xyz, accel_xyz)         # rad/s, m/s^2, body frame I
    sys.push_rotors(t_ns, [w1, w2, w3, w4])          # rotor0/sensor.yaml's unit
    sys.push_images(t_ns, left_uint8, right_uint8)   # (H, W) uint8 arrays
    est = sys.latest()                              # dict: p_WI, q_WI (w,x,y,z), F_ext_I, cov_F_I, ...
    h = sys.history()                               # every estimate as (N, k) arrays

Errors in configuration files raise :class:`ConfigError`, in dataset files
:class:`DatasetError` (both ``ValueError``); each message names the file and the field.
The example script ``python/examples/push_samples.py`` does the second form end to end.
"""
from ._core import (  # noqa: F401  (the package's API)
    ConfigError,
    DatasetError,
    System,
    __version__,
    git_sha,
    run_dataset,
)

__all__ = ["System", "run_dataset", "ConfigError", "DatasetError", "__version__", "git_sha"]
