"""`musclefem.fit`: `musclefem fit` from Python, checked by recovering a known parameter
from a curve made by the closed form of the law, and against the command line's files."""

import subprocess

import numpy as np
import pytest

import musclefem

from helpers import CLI, CUBE, cube_dict, neo_hookean_uniaxial

# The example cube (1 cm, mu = 10 kPa, D = 2e-5 /Pa) pulled to 1.5 in 1 s; the
# "measurement" is the closed-form reaction of a cube with mu = 12 kPa, every 0.1 s.
TRUE_MU = 1.2e4
TIMES = np.linspace(0.1, 1.0, 10)
FORCES = np.array([neo_hookean_uniaxial(TRUE_MU, 2e-5, 1 + 0.5 * t) * 1e-4 for t in TIMES])


def test_a_scene_fit_recovers_the_shear_modulus_of_the_closed_form_curve(tmp_path):
    fitted = musclefem.fit(
        (TIMES, FORCES), ["mu"], scene=str(CUBE), y="reaction_cube.x1.x_n", out=str(tmp_path)
    )
    mu = fitted["parameters"]["mu"]
    # The cube deforms homogeneously and hex8-fbar represents that exactly: the fit is
    # limited by the Newton tolerance of the runs (7e-11 relative on the 2-core machine).
    assert mu == pytest.approx(TRUE_MU, rel=1e-8)
    table = fitted["table"]
    assert table["parameter"] == ["mu"] and table["start"][0] == 1e4
    assert table["ci95_low"][0] <= mu <= table["ci95_high"][0]
    assert not table["at_bound"][0]
    curve = fitted["curve"]
    assert list(curve) == ["time_s", "measured_reaction_cube.x1.x_n", "fitted_reaction_cube.x1.x_n"]
    np.testing.assert_array_equal(curve["time_s"], TIMES)
    np.testing.assert_allclose(curve["fitted_reaction_cube.x1.x_n"], FORCES, rtol=1e-6)
    assert fitted["fitted_curve"]["x"].shape == fitted["fitted_curve"]["y"].shape
    assert fitted["r_squared"] > 0.999999 and fitted["left_out"] == 0
    assert "RMS residual" in fitted["summary"]
    for name in ["fit.csv", "fit_curve.csv", "fit.txt", "fit.png"]:
        assert (tmp_path / name).is_file(), name
    with pytest.raises(musclefem.MusclefemError, match="a previous fit"):
        musclefem.fit((TIMES, FORCES), "mu", scene=str(CUBE), y="reaction_cube.x1.x_n",
                      out=str(tmp_path))


def test_an_elongation_fit_recovers_the_hill_parameters_of_its_curve():
    """The cheap homogeneous elongation test (cylinder, sliding grips, 72 elements, 0.2 s
    increments) made with c = 450 Pa and A = 3.2, fitted from Table 1's values."""
    options = dict(shape="cylinder", grips="sliding", mesh_size=8.75, time_step=0.2)
    curve = musclefem.elongate("passive", **options, c=450.0, A=3.2)
    data = {name: curve[name] for name in ["engineering_strain", "engineering_stress_pa"]}
    fitted = musclefem.fit(data, ["c", "A"], test="passive", **options)
    table = fitted["table"]
    assert abs(table["start"][0] / 450.0 - 1) > 0.1 and abs(table["start"][1] / 3.2 - 1) > 0.1
    assert fitted["parameters"]["c"] == pytest.approx(450.0, rel=1e-4)
    assert fitted["parameters"]["A"] == pytest.approx(3.2, rel=1e-4)
    assert list(fitted["curve"]) == [
        "engineering_strain", "measured_stress_pa", "fitted_stress_pa"
    ]


@pytest.mark.skipif(not CLI.exists(), reason="needs target/release/musclefem")
def test_the_fit_of_a_csv_file_is_the_command_lines(tmp_path):
    data = tmp_path / "measured.csv"
    data.write_text("time_s,force_n\n" + "".join(f"{t},{f}\n" for t, f in zip(TIMES, FORCES)))
    options = ["--scene", str(CUBE), "--y", "reaction_cube.x1.x_n", "--stress-column", "force_n"]
    options += ["--params", "mu", "--start", "mu=9000"]
    subprocess.run([str(CLI), "fit", "--data", str(data), *options, "--out", str(tmp_path / "cli")],
                   check=True, capture_output=True)
    fitted = musclefem.fit(str(data), ["mu"], scene=musclefem.Scene(str(CUBE)),
                           y="reaction_cube.x1.x_n", stress_column="force_n", start={"mu": 9000},
                           out=str(tmp_path / "py"))
    for name in ["fit.csv", "fit_curve.csv"]:
        assert (tmp_path / "py" / name).read_text() == (tmp_path / "cli" / name).read_text()
    # A dict of columns is the same curve as the file.
    again = musclefem.fit({"time_s": TIMES, "force_n": FORCES}, "mu", scene=str(CUBE),
                          y="reaction_cube.x1.x_n", stress_column="force_n", start={"mu": 9000})
    assert again["parameters"] == fitted["parameters"]


def test_bad_fits_raise_the_command_lines_message(tmp_path):
    data = (TIMES, FORCES)
    scene = dict(scene=str(CUBE), y="reaction_cube.x1.x_n")
    with pytest.raises(musclefem.MusclefemError, match="no parameter 'sigma0'"):
        musclefem.fit(data, ["sigma0"], **scene)
    with pytest.raises(musclefem.MusclefemError, match="no history column 'force'"):
        musclefem.fit(data, ["mu"], scene=str(CUBE), y="force")
    with pytest.raises(musclefem.MusclefemError, match="do not apply to a scene"):
        musclefem.fit(data, ["mu"], shape="cylinder", **scene)
    with pytest.raises(musclefem.MusclefemError, match="cannot be used with"):
        musclefem.fit(data, ["mu"], test="active", **scene)
    with pytest.raises(musclefem.MusclefemError, match="names its own columns"):
        musclefem.fit(data, ["mu"], stress_column="force_n", **scene)
    with pytest.raises(musclefem.MusclefemError, match="not among --params"):
        musclefem.fit(data, ["mu"], start={"D": 1e-5}, **scene)
    with pytest.raises(musclefem.MusclefemError, match="has no file"):
        musclefem.fit(data, ["mu"], scene=musclefem.Scene.from_dict(
            cube_dict()), y="reaction_cube.x1.x_n")
    # The elongation test's Hill parameters: n2 is the test's to set.
    with pytest.raises(musclefem.MusclefemError, match="the test sets the activation"):
        musclefem.fit(data, ["n2"])
