"""phase0 loader and flight-phase segmentation (vid_eval.core.phases): events, windows, edge cases."""
from __future__ import annotations

import numpy as np
import pytest

from phase_testdata import write_phases
from vid_eval.errors import InputFormatError
from vid_eval.tools.loaders import find_phases, load_phases
from vid_eval.core.phases import segment_phases
from vid_eval.core.series import ScalarSeries

S = 1_000_000_000  # ns per s
T0 = 10**18


def _series(phases, rate_hz=10):
    """phase0 at ``rate_hz`` from T0: one value per sample."""
    t = T0 + np.arange(len(phases), dtype=np.int64) * (S // rate_hz)
    return ScalarSeries(t, np.asarray(phases, dtype=np.int64))


def test_loader_reads_a_good_file(tmp_path):
    t = T0 + np.arange(6, dtype=np.int64) * 5_000_000
    path = write_phases(tmp_path / "mav0" / "phase0" / "data.csv", t, np.array([0, 0, 1, 1, 1, 0]))
    s = load_phases(path)
    np.testing.assert_array_equal(s.t_ns, t)
    np.testing.assert_array_equal(s.values, [0, 0, 1, 1, 1, 0])
    assert s.source == str(path)
    gt = tmp_path / "mav0" / "state_groundtruth_estimate0" / "data.csv"
    assert find_phases(gt) == path.resolve()  # found next to any mav0/<stream>/data.csv
    assert find_phases(tmp_path / "elsewhere" / "gt.txt") is None


@pytest.mark.parametrize("value", ["2", "0.5", "-1"])
def test_loader_refuses_a_phase_other_than_0_or_1(tmp_path, value):
    path = tmp_path / "data.csv"
    path.write_text(f"#timestamp [ns],phase\n100,0\n200,1\n300,{value}\n400,1\n")
    with pytest.raises(InputFormatError) as exc:
        load_phases(path)
    assert str(exc.value) == (f"{path}:4: phase0 CSV: column 2 'phase': expected 0 (on the ground) "
                              f"or 1 (airborne), got {float(value):g}")


def test_loader_names_file_line_and_column_of_a_value_that_is_not_a_number(tmp_path):
    path = tmp_path / "data.csv"
    path.write_text("#timestamp [ns],phase\n100,0\n\n200,airborne\n")
    with pytest.raises(InputFormatError, match=r"data.csv:4: phase0 CSV: column 2 'phase': "
                                               r"value 'airborne' is not a number"):
        load_phases(path)


@pytest.mark.parametrize("times, kind", [((100, 300, 200), "decreasing"), ((100, 200, 200), "repeated")])
def test_loader_refuses_unsorted_time(tmp_path, times, kind):
    path = tmp_path / "data.csv"
    path.write_text("#timestamp [ns],phase\n" + "".join(f"{t},0\n" for t in times))
    with pytest.raises(InputFormatError, match=rf"data.csv:4: .*not strictly increasing \({kind}"):
        load_phases(path)


def test_loader_checks_the_header_and_the_column_count(tmp_path):
    path = tmp_path / "data.csv"
    path.write_text("#timestamp [ns],state\n100,0\n")
    with pytest.raises(InputFormatError, match=r":1: .*header column 2 is 'state', expected 'phase'"):
        load_phases(path)
    path.write_text("#timestamp [ns],phase\n100,0,1\n")
    with pytest.raises(InputFormatError, match=r":2: phase0 CSV: expected 2 columns, found 3"):
        load_phases(path)


def test_events_intervals_and_windows():
    # 10 Hz: landed 0-2.9 s, airborne 3.0-6.9 s, landed 7.0-9.9 s
    seg = segment_phases(_series([0] * 30 + [1] * 40 + [0] * 30), window_s=1.0)
    assert [(iv.phase, iv.t0_ns - T0, iv.t1_ns - T0) for iv in seg.intervals] == [
        ("landed", 0, 3 * S), ("airborne", 3 * S, 7 * S), ("landed", 7 * S, 9_900_000_000)]
    assert [(e.name, e.t_ns - T0, e.w0_ns - T0, e.w1_ns - T0) for e in seg.events] == [
        ("lift-off 1", 3 * S, 2_500_000_000, 3_500_000_000),
        ("touchdown 1", 7 * S, 6_500_000_000, 7_500_000_000)]
    assert seg.segment_names() == ["landed", "airborne", "lift-off 1", "touchdown 1"]
    t = T0 + np.array([0, 2.4, 2.5, 3.0, 3.5, 3.6, 6.4, 7.2, 9.9, 10.0]) * S
    t = t.astype(np.int64)
    assert seg.mask(t, "landed").tolist() == [1, 1, 0, 0, 0, 0, 0, 0, 1, 0]
    assert seg.mask(t, "airborne").tolist() == [0, 0, 0, 0, 0, 1, 1, 0, 0, 0]
    assert seg.mask(t, "lift-off 1").tolist() == [0, 0, 1, 1, 1, 0, 0, 0, 0, 0]  # closed window
    assert seg.mask(t, "touchdown 1").tolist() == [0, 0, 0, 0, 0, 0, 0, 1, 0, 0]
    assert seg.duration_s("landed") == pytest.approx(2.5 + 2.4)  # 9.9 s span, windows cut 1 s
    assert seg.duration_s("airborne") == pytest.approx(3.0)
    assert seg.duration_s("touchdown 1") == pytest.approx(1.0)
    d = seg.as_dict()
    assert d["events"][0] == {"name": "lift-off 1", "kind": "lift-off", "t_ns": T0 + 3 * S,
                              "t_s": 3.0, "window_t0_s": 2.5, "window_t1_s": 3.5}


def test_windows_are_clipped_at_the_sequence_ends():
    seg = segment_phases(_series([0] * 2 + [1] * 50 + [0] * 3), window_s=1.0)
    lift, touch = seg.events
    assert (lift.t_ns - T0, lift.w0_ns - T0, lift.w1_ns - T0) == (200_000_000, 0, 700_000_000)
    assert (touch.t_ns - T0, touch.w0_ns - T0, touch.w1_ns - T0) == (
        5_200_000_000, 4_700_000_000, 5_400_000_000)
    assert seg.duration_s("lift-off 1") == pytest.approx(0.7)
    assert seg.duration_s("landed") == pytest.approx(0.0)  # both landed bits lie in windows


def test_a_sequence_that_never_lifts_off():
    seg = segment_phases(_series([0] * 20))
    assert seg.events == []
    assert [iv.phase for iv in seg.intervals] == ["landed"]
    assert seg.segment_names() == ["landed", "airborne"]
    t = seg.intervals[0].t0_ns + np.arange(0, 25, dtype=np.int64) * (S // 10)
    assert seg.mask(t, "landed").tolist() == [True] * 20 + [False] * 5  # after the end: no phase
    assert not seg.mask(t, "airborne").any()
    assert seg.duration_s("airborne") == 0.0
    after = seg.landed_after(t, 1.0)
    assert len(after) == 1 and after[0][1].tolist() == [False] * 10 + [True] * 10 + [False] * 5


def test_a_sequence_that_starts_airborne():
    seg = segment_phases(_series([1] * 40 + [0] * 30 + [1] * 30), window_s=0.4)
    assert [iv.phase for iv in seg.intervals] == ["airborne", "landed", "airborne"]
    assert [e.name for e in seg.events] == ["touchdown 1", "lift-off 1"]  # numbered per kind
    assert seg.events[0].w0_ns - T0 == 3_800_000_000 and seg.events[0].w1_ns - T0 == 4_200_000_000
    # on the ground since touchdown 1 at 4.0 s: 1 s later, outside lift-off 1's window (6.8 s)
    t = T0 + (np.arange(0, 100, dtype=np.int64) * (S // 10))
    (iv, m), = seg.landed_after(t, 1.0)
    assert iv.t0_ns - T0 == 4 * S
    assert (t[m] - T0).tolist() == [k * (S // 10) for k in range(50, 68)]


def test_close_events_have_overlapping_windows():
    # a bounce: touchdown at 2.0 s, lift-off again at 2.3 s
    seg = segment_phases(_series([1] * 20 + [0] * 3 + [1] * 20))
    td, lo = seg.events
    t = np.array([T0 + 2_100_000_000])
    assert seg.mask(t, td.name)[0] and seg.mask(t, lo.name)[0]
    assert not seg.mask(t, "landed")[0]
    assert seg.duration_s("landed") == 0.0
    assert seg.duration_s("airborne") == pytest.approx(4.2 - 1.3)  # one merged window 1.5-2.8 s


def test_window_must_be_positive():
    with pytest.raises(ValueError, match="positive"):
        segment_phases(_series([0, 1]), window_s=0.0)
