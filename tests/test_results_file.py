"""Results files read back consistently after a kill in the middle of a flush."""

from __future__ import annotations

import h5py
import numpy as np

from orchestrator.results import ResultsWriter, read_results


def test_a_flush_cut_between_two_series_reads_back_as_the_rows_every_series_holds(tmp_path) -> None:
    path = tmp_path / "run.h5"
    writer = ResultsWriter(path, {"time": (), "bodies/float/displacement": (6,)}, {"scenario": "x"})
    for k in range(5):
        writer.append({"time": 0.1 * k, "bodies/float/displacement": np.full(6, float(k))})
    writer.flush()
    # What a SIGKILL between two datasets' resizes leaves: one series a flush longer than the other.
    writer.datasets["time"].resize(8, axis=0)
    writer.datasets["time"][5:8] = [0.5, 0.6, 0.7]
    writer.file.flush()
    writer.file.close()
    with h5py.File(path, "r") as f:
        assert len(f["time"]) == 8 and len(f["bodies/float/displacement"]) == 5
    data = read_results(path)
    assert len(data["time"]) == 5 and data["bodies/float/displacement"].shape == (5, 6)
    np.testing.assert_array_equal(data["time"], 0.1 * np.arange(5))
    assert data["attrs"]["status"] == "running"


def test_rows_given_as_flat_values_land_in_their_series_and_missing_series_read_nan(tmp_path) -> None:
    """append_values: the leading columns of a row (row_layout order), later series by name, the rest NaN; the
    same file as row-by-row dicts."""
    from orchestrator.results.results_file import row_layout

    series = {"time": (), "bodies/float/displacement": (6,), "energy/kinetic": (), "control/commands": (2,),
              "control/fault": ()}
    layout = row_layout(series)
    assert layout["bodies/float/displacement"][0] == slice(1, 7) and layout["control/commands"][0] == slice(8, 10)
    flat, by_dict = ResultsWriter(tmp_path / "a.h5", series, {}), ResultsWriter(tmp_path / "b.h5", series, {})
    for k in range(3):
        lead = np.concatenate([[0.5 * k], np.arange(6.0) + k, [10.0 * k]])
        flat.append_values(lead, {"control/commands": [k, -k]})
        by_dict.append({"time": 0.5 * k, "bodies/float/displacement": np.arange(6.0) + k, "energy/kinetic": 10.0 * k,
                        "control/commands": np.array([k, -k])})
    flat.close()
    by_dict.close()
    a, b = read_results(tmp_path / "a.h5"), read_results(tmp_path / "b.h5")
    for name in series:
        np.testing.assert_array_equal(a[name], b[name])
    np.testing.assert_array_equal(a["bodies/float/displacement"][2], np.arange(6.0) + 2)
    np.testing.assert_array_equal(a["control/commands"][:, 1], [0, -1, -2])
    assert np.isnan(a["control/fault"]).all() and a["energy/kinetic"].tolist() == [0.0, 10.0, 20.0]


def test_rows_written_over_several_flushes_read_back_exactly(tmp_path) -> None:
    """Flushes of a few rows each (buffer of 3 rows, one forced flush in between) append every row after the last:
    the file holds each value written, in order, for scalar and vector series."""
    series = {"time": (), "bodies/float/velocity": (6,), "ptos/pto/power": ()}
    writer = ResultsWriter(tmp_path / "run.h5", series, {}, buffer_rows=3)
    rows = np.random.default_rng(7).normal(size=(11, 8))
    for k, row in enumerate(rows):
        line = writer.next_line()
        line[:8] = row
        writer.commit_line(8)
        if k == 4:
            writer.flush()
    writer.close()
    data = read_results(tmp_path / "run.h5")
    np.testing.assert_array_equal(data["time"], rows[:, 0])
    np.testing.assert_array_equal(data["bodies/float/velocity"], rows[:, 1:7])
    np.testing.assert_array_equal(data["ptos/pto/power"], rows[:, 7])
