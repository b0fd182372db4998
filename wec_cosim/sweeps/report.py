"""The text ``wec-cosim sweep`` prints at the end: counts, failures and the power table."""

from __future__ import annotations

import numpy as np

from .matrices import read_matrices
from .runner import SweepOutcome
from .store import open_sweep_file

MAX_FAILURES_SHOWN = 5


def format_outcome(outcome: SweepOutcome) -> str:
    with open_sweep_file(outcome.path) as f:
        cases = f["cases"]
        ids = {c.id for c in outcome.plan.cases}
        finished = [cases[i] for i in ids if i in cases]
        failures = [g for g in finished if g.attrs["status"] != "ok"]
        lines = [f"{outcome.path}: {len(finished)} of {outcome.total} cases finished, {len(failures)} failed "
                 f"(this run: {outcome.ran} case{'s' if outcome.ran != 1 else ''} in {outcome.wall_time:.1f} s)"]
        for g in failures[:MAX_FAILURES_SHOWN]:
            lines.append(f"  failed: {g.attrs['label']}: {g.attrs['error']}")
        if len(failures) > MAX_FAILURES_SHOWN:
            lines.append(f"  ... and {len(failures) - MAX_FAILURES_SHOWN} more (attribute `error` of /cases/<id>)")
        lines += _power_table(f)
    return "\n".join(lines)


def _power_table(f) -> list[str]:  # noqa: ANN001
    m = read_matrices(f)
    if "mean_power" not in m.data:
        return []
    keep = [i for i, n in enumerate(m.shape) if n > 1]
    power = np.squeeze(m.data["mean_power"], axis=tuple(i for i in range(len(m.shape)) if i not in keep)) / 1e3
    if len(keep) > 2:
        return [f"mean power (kW) over {len(keep)} swept keys: see /matrices/mean_power or `wec-cosim plot "
                f"{f.filename}`"]
    if len(keep) <= 1:
        header = m.keys[keep[0]] if keep else "the single grid cell"
        labels = m.values[keep[0]] if keep else [""]
        lines = [f"mean power (kW) against {header}"]
        lines += [f"  {_cell(v):>12}{_cell(p):>12}" for v, p in zip(labels, np.atleast_1d(power), strict=True)]
        return lines
    rows, cols = keep
    lines = [f"mean power (kW); rows {m.keys[rows]}, columns {m.keys[cols]}",
             " " * 14 + "".join(f"{_cell(v):>10}" for v in m.values[cols])]
    for v, row in zip(m.values[rows], power, strict=True):
        lines.append(f"  {_cell(v):>12}" + "".join(f"{_cell(x):>10}" for x in row))
    return lines


def _cell(value) -> str:  # noqa: ANN001
    if isinstance(value, (float, np.floating)):
        return "-" if not np.isfinite(value) else f"{value:.4g}"
    return str(value)
