"""Does vid_live's summary.json count exactly the faults vid_replay injected?

vid_replay's ``--report`` lists every fault as the receiver should count it; vid_live's
``summary.json`` ``faults`` block has one counter per stream and kind. The rule, per stream:
a dropped image, a late message (dropped by the reorder window) and an image withheld by a
camera stall each leave one gap (``missing``); a duplicated IMU message is a ``duplicate``; a
delayed message that arrives after a later one is ``reordered``; a payload that does not
decode or validate is ``malformed`` on its channel; nothing is dropped for overload.
"""
from __future__ import annotations

from typing import Dict, List

STREAMS = ("imu", "cam0", "cam1", "rotors", "thrust")
DEFAULT_CHANNELS = {"IMU": "imu", "CAM0": "cam0", "CAM1": "cam1", "ROTORS": "rotors",
                    "THRUST": "thrust"}


def fault_mismatches(report: dict, summary: dict,
                     channel_stream: Dict[str, str] = DEFAULT_CHANNELS) -> List[str]:
    """Every counter of ``summary['faults']`` that differs from what ``report['faults']``
    injected, one line each (``"cam0.missing: counted 12, injected 13"``); [] when all agree."""
    inj, got = report["faults"], summary["faults"]
    want: Dict[str, int] = {}
    for s in STREAMS:
        late = inj["late"].get(s, 0)
        want[f"{s}.late"] = late
        want[f"{s}.reordered"] = inj["reordered_arrivals"].get(s, 0)
        want[f"{s}.missing"] = (late + inj["images_dropped"].get(s, 0)
                                + inj["stall_images"].get(s, 0))
        want[f"{s}.malformed"] = 0
        want[f"{s}.duplicate"] = 0
    want["imu.duplicate"] = inj["imu_duplicated"]
    for channel, n in inj["malformed"].items():
        want[f"{channel_stream[channel]}.malformed"] += n
    want["camera_stalls"] = inj["camera_stalls"]
    want["frames_dropped_overload"] = 0
    out = []
    for key, n in want.items():
        if key not in got:
            if n:
                out.append(f"{key}: not in summary.json, injected {n}")
            continue
        if got[key] != n:
            out.append(f"{key}: counted {got[key]}, injected {n}")
    return out
