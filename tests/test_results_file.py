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
