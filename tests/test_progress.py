"""Progress bar of long runs: silent on short runs, a percentage and time left on long ones, erased at the end."""

from __future__ import annotations

import io

from orchestrator.progress import ProgressBar


def test_short_runs_print_nothing() -> None:
    stream = io.StringIO()
    bar = ProgressBar(0.0, 100.0, delay=3600.0, stream=stream)
    for t in range(101):
        bar.update(float(t))
    bar.close()
    assert stream.getvalue() == ""


def test_long_runs_show_fraction_and_are_erased() -> None:
    stream = io.StringIO()
    bar = ProgressBar(0.0, 200.0, delay=0.0, interval=0.0, width=10, stream=stream, terminal=True)
    bar.update(60.0)
    shown = stream.getvalue()
    assert "[###.......]" in shown and " 30.0 %" in shown and "t =     60.00 s" in shown and "left" in shown
    bar.close()
    assert stream.getvalue().endswith("\r") and not bar.shown


def test_disabled_bar_is_silent() -> None:
    stream = io.StringIO()
    bar = ProgressBar(0.0, 1.0, enabled=False, delay=0.0, interval=0.0, stream=stream)
    bar.update(0.5)
    bar.close()
    assert stream.getvalue() == ""


# ----------------------------------------------------------------------------- BEM solves
def tiny_body():
    from hydro_fmu.bem import BemBody, BodyGeometry

    return BemBody("can", BodyGeometry("vertical_cylinder", radius=1.0, draft=1.0, panel_size=0.5), (0.0, 0.0, -0.5))


def test_bem_solve_shows_each_frequency_and_equals_capytaines_own_fill_dataset(tmp_path) -> None:
    """A tiny Capytaine problem (3 frequencies): one log line when the solve starts, then the bar names every
    frequency and the infinite one, and is erased. Solved one frequency at a time, the coefficients are
    bit for bit those of Capytaine's fill_dataset over the whole grid; a cache hit shows nothing."""
    import capytaine as cpt
    import numpy as np
    import xarray as xr

    from hydro_fmu.bem import BemSettings, _floating_body, cached_database
    from orchestrator.progress import BemProgress

    stream, log = io.StringIO(), []
    settings = BemSettings(omega=(0.5, 1.0, 2.0), headings_deg=(0.0,))
    shown = BemProgress(1, log=log.append, stream=stream, delay=0.0, interval=0.0, terminal=True)
    hdb, _, computed = cached_database([tiny_body()], settings, tmp_path, progress=shown)
    shown.close()
    assert computed
    assert log == ["computing the hydrodynamic database with Capytaine: 3 frequencies x 1 heading(s) and the "
                   "infinite frequency (this can take minutes) ..."]
    text = stream.getvalue()
    for k, where in enumerate(("omega = 0.5 rad/s", "omega = 1 rad/s", "omega = 2 rad/s", "infinite frequency"), 1):
        assert f"{25.0 * k:5.1f} %  BEM frequency {k} of 4 ({where})" in text
    assert text.endswith("\r") and not shown.bar.shown

    body = _floating_body(tiny_body())
    dofs = list(body.dofs)
    common = {"water_depth": [np.inf], "rho": [settings.rho], "g": [settings.g], "radiating_dof": dofs,
              "influenced_dof": dofs}
    own = cpt.BEMSolver().fill_dataset(xr.Dataset(coords={"omega": list(settings.omega), "wave_direction": [0.0],
                                                          **common}), body, progress_bar=False)
    np.testing.assert_array_equal(hdb.added_mass, own["added_mass"].transpose("omega", "influenced_dof",
                                                                              "radiating_dof").values)
    # (the BEMIO file keeps the excitation divided by rho g: equal to the last bits)
    np.testing.assert_allclose(hdb.excitation[0], np.conj(own["excitation_force"].transpose(
        "wave_direction", "omega", "influenced_dof").values[0]), rtol=1e-14, atol=0)

    again = BemProgress(1, log=log.append, stream=stream, delay=0.0, interval=0.0, terminal=True)
    _, _, computed = cached_database([tiny_body()], settings, tmp_path, progress=again)
    assert not computed and again.bar is None and len(log) == 1


def test_hydro_command_announces_the_solve_and_its_time(tmp_path, capsys) -> None:
    from wec_cosim.cli import main

    scenario = tmp_path / "tiny.toml"
    scenario.write_text("""
name = "tiny"
[simulation]
duration = 10.0
step = 0.1
[waves]
kind = "regular"
height = 1.0
period = 6.0
[hydro]
omega = { start = 0.5, stop = 1.5, step = 0.5 }
cache_dir = "cache"
[[bodies]]
name = "can"
cg = [0.0, 0.0, -0.5]
dofs = ["heave"]
[bodies.geometry]
shape = "vertical_cylinder"
radius = 1.0
draft = 1.0
panel_size = 0.5
""")
    assert main(["hydro", str(scenario)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("computing the hydrodynamic database with Capytaine: 3 frequencies x 1 heading(s)")
    assert out[1].startswith(f"computed hydrodynamic database {tmp_path / 'cache'}") and out[1].endswith(" s")
    assert out[2].endswith("3 frequencies 0.5..1.5 rad/s, 1 headings (" + out[2].split("(", 1)[1])


# ----------------------------------------------------------------------------- terminal or log file
def test_a_log_file_gets_a_plain_line_every_five_percent() -> None:
    """Not a terminal (a file, a pipe, a notebook): no carriage-return frames, one line per 5 % of the run, each
    with the percentage, the position and the time left; nothing to erase at the end."""
    stream = io.StringIO()
    bar = ProgressBar(0.0, 200.0, delay=0.0, interval=0.0, stream=stream)
    assert not bar.terminal
    for k in range(1, 2001):
        bar.update(k / 10)
    bar.close()
    lines = stream.getvalue().splitlines()
    assert "\r" not in stream.getvalue()
    assert len(lines) == 20
    assert [float(line.split("%")[0]) for line in lines] == [5.0 * k for k in range(1, 21)]
    assert "t =     10.00 s" in lines[0] and "left" in lines[0]


def test_a_jump_past_several_steps_prints_one_line() -> None:
    stream = io.StringIO()
    bar = ProgressBar(0.0, 100.0, delay=0.0, interval=0.0, stream=stream)
    bar.update(1.0)
    bar.update(37.0)
    bar.update(38.0)
    bar.update(40.0)
    assert [line.split("%")[0].strip() for line in stream.getvalue().splitlines()] == ["37.0", "40.0"]


def test_a_terminal_is_recognised() -> None:
    """A pseudo-terminal gets the redrawn bar; the same bar on a pipe prints lines."""
    import os

    main, other = os.openpty()
    try:
        with os.fdopen(other, "w", closefd=False) as tty:
            assert ProgressBar(0.0, 1.0, stream=tty).terminal
    finally:
        os.close(main)
        os.close(other)
    read, write = os.pipe()
    try:
        with os.fdopen(write, "w", closefd=False) as pipe:
            assert not ProgressBar(0.0, 1.0, stream=pipe).terminal
    finally:
        os.close(read)
        os.close(write)
