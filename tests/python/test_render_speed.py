"""Renderer speed (docs/results.md: a 60 s stereo vid17_like renders in 81 s on one core, target
<= 60 s): a ratchet on the CPU time vid_sim takes for 3 s of rendered stereo vid17_like (the
simulator's set-up, rendering, PNG encoding and writing; one thread). CPU time, not wall time:
on a loaded machine the wall time of the same run varied 18-28 s, its CPU time by 3 %.

Measured at 182d56e (seed 1, 91 stereo frames): user + sys 3.03 / 3.10 / 3.00 s over three runs
(sd 0.05): ratchet at mean + 3 sd = 3.20 s (tighter than 1.2 x = 3.64 s). The target is a wall
time on 60 s, which this 3 s run cannot tell honestly (set-up cost, I/O): it stays in
docs/results.md, measured by `bench_sim_render` and the 60 s render."""
import resource
import subprocess

from ratchets import ratchet
from test_vid_run_helpers import REPO, program

CPU_S = 3.04


def test_rendering_cpu_time_ratchet(tmp_path):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run([str(program("vid_sim")), "--scenario", str(REPO / "config" / "sim" / "vid17_like.yaml"),
                        "--out", str(tmp_path / "seq"), "--seed", "1", "--duration", "3", "--quiet"],
                       capture_output=True, text=True, timeout=600)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    assert r.returncode == 0, r.stderr
    frames = len(list((tmp_path / "seq" / "mav0" / "cam0" / "data").glob("*.png")))
    assert frames == 91 and len(list((tmp_path / "seq" / "mav0" / "cam1" / "data").glob("*.png"))) == frames
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    print(f"[render] {frames} stereo frames, {1e3 * cpu / frames:.1f} ms CPU per frame")
    ratchet("vid_sim CPU time, 3 s rendered stereo vid17_like [s]", cpu, 3.20, CPU_S)
