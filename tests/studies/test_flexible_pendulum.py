"""The flexible pendulum study (studies/flexible_pendulum.py), its first 0.25 s: corotate's
floating-frame body and Exudyn's, built from corotate's basis, follow the full co-rotational link,
and both fall like the rigid compound pendulum at first (the link is 20x stiffer in bending
than the pendulum is slow: its first clamped frequency is 1.6 Hz, the pendulum's 0.6 Hz)."""

import csv

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from studies.flexible_pendulum import H, L, main

G = 9.81


def _rigid_angle(t):
    """The rigid link's angle below the horizontal: theta'' = (m g L/2 / I) cos theta, with I about
    the hinge axis (through the root face's centre) = m (L^2/3 + H^2/12)."""
    k = G * L / 2 / (L**2 / 3 + H**2 / 12)
    sol = solve_ivp(lambda _t, y: [y[1], k * np.cos(y[0])], (0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-12, atol=1e-12)
    return sol.y[0]


def test_exudyn_s_ffrf_body_follows_the_full_co_rotational_link(tmp_path):
    pytest.importorskip("exudyn")
    pytest.importorskip("matplotlib")
    assert main(["--out", str(tmp_path), "--dt", "1e-3", "--duration", "0.25", "--modes", "8"]) == 0
    with (tmp_path / "errors.csv").open() as f:
        table = {row["run"]: row for row in csv.DictReader(f)}
    errors = {name: float(row["max_error_over_L"]) for name, row in table.items()}
    full = errors["full co-rotational, dt = 0.0005 s"]
    face, axis = errors["Exudyn FFRF, root face, 8 modes"], errors["Exudyn FFRF, hinge axis, 8 modes"]
    # The fine backward-Euler run is within its O(dt) error of the extrapolation (measured
    # 0.0011 L); the Exudyn runs, with either frame, within 0.0019 L.
    assert full < 0.002
    assert face < 0.003 and axis < 0.003
    # corotate's floating frame, stiffened by its inertial loads and gravity, within 0.1 % of L of
    # the full link (measured 0.06 %; over the whole 2 s, 0.15-0.19 %).
    assert errors["corotate FFRF, stiffened, 8 modes"] < 0.001
    # The linear one keeps the exact energy of its kinematics (measured 1e-7 of m g L / 2 over 2 s).
    linear = table["corotate FFRF, linear, 8 modes"]
    assert float(linear["max_energy_change_over_mgL2"]) < 1e-5
    # Exudyn runs the same model from the exported basis: by 0.25 s its path is within 1.1e-7 L
    # of corotate's and its energy kept to 5.7e-7 (measured). With gravity as Exudyn's own
    # mass-proportional load the export gave 1.9e-4 L and 1.6e-3.
    exudyn = table["Exudyn FFRF, root face, 8 modes"]
    assert float(exudyn["max_gap_to_corotate_ffrf_over_L"]) < 1e-5
    assert float(exudyn["max_energy_change_over_mgL2"]) < 1e-5
    paths = np.loadtxt(tmp_path / "tip_paths.csv", delimiter=",", skiprows=1)
    t, x, z = paths[:, 0], paths[:, 1], paths[:, 2]
    np.testing.assert_allclose([x[0], z[0]], [L, 0.0], atol=1e-14)
    angle = np.arctan2(-z, x)
    rigid = _rigid_angle(t)
    # A flexible link lags the rigid one (its tip starts to fall at g, not at 1.5 g); by 0.25 s
    # the angles agree within 1.5 % (measured: 0.75 % behind).
    assert np.abs(angle[-1] - rigid[-1]) < 0.015 * rigid[-1]
    assert (tmp_path / "flexible_pendulum.png").stat().st_size > 20_000
