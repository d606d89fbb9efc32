"""Materials defined in Python (`musclefem.register_material`): a neo-Hookean law written
with NumPy against the built-in one, in a material point and in a scene; state variables;
and a failing law reported by name."""

import numpy as np
import pytest

import musclefem

from helpers import CUBE, cube_dict


def neo_hookean(F, params, **_):
    """Cauchy stress of W = mu/2 (I1bar - 3) + (J - 1)^2 / D, written here from the law:
    sigma = mu/J dev(Bbar) + 2 (J - 1)/D I, Bbar = J^(-2/3) F F^T."""
    mu, d = params["mu"], params["D"]
    j = np.linalg.det(F)[:, None, None]
    b_bar = j ** (-2 / 3) * F @ F.transpose(0, 2, 1)
    identity = np.eye(3)
    deviator = b_bar - np.trace(b_bar, axis1=1, axis2=2)[:, None, None] / 3 * identity
    return mu / j * deviator + 2 * (j - 1) / d * identity


NEO_HOOKEAN_PARAMETERS = {
    "mu": {"default": 11370.0, "unit": "Pa", "lower": 1e-300, "description": "shear modulus"},
    "D": {"default": 5e-9, "unit": "1/Pa", "lower": 1e-300},
}


def test_a_neo_hookean_in_numpy_is_the_built_in_one_at_a_material_point():
    musclefem.register_material("numpy-neo-hookean", neo_hookean, NEO_HOOKEAN_PARAMETERS)
    listed = {m["name"]: m for m in musclefem.materials()}["numpy-neo-hookean"]
    assert [p["name"] for p in listed["parameters"]] == ["mu", "D"]
    assert listed["parameters"][0]["unit"] == "Pa"
    times, stretches = [0.0, 1.0, 2.0], [1.0, 1.5, 0.7]
    ours = musclefem.MaterialPoint("numpy-neo-hookean", mu=1e4, D=2e-5).uniaxial(
        times, stretches, dt=0.01
    )
    built_in = musclefem.MaterialPoint("neo-hookean", mu=1e4, D=2e-5).uniaxial(
        times, stretches, dt=0.01
    )
    for column, values in built_in.items():
        np.testing.assert_allclose(ours[column], values, rtol=1e-10, atol=0, err_msg=column)
    assert np.abs(built_in["engineering_stress_pa"]).max() > 1e3


def plain_newton(scene):
    """The scene with plain Newton (the tangent predictor, every linear solve to the
    solver's own tolerance), whose iterations show the tangent's quality alone: with the
    default extrapolated first guess the tangent by central differences takes 4 iterations
    in two increments where the analytic one takes 3 (its error then decides the last)."""
    scene["step"]["implicit"].update(extrapolate=False, inexact_newton=False)
    return scene


def test_a_scene_runs_a_python_material_as_the_built_in_one():
    musclefem.register_material("numpy-neo-hookean", neo_hookean, NEO_HOOKEAN_PARAMETERS)
    scene = cube_dict()
    scene["materials"][0]["model"] = "numpy-neo-hookean"
    ours = musclefem.Scene.from_dict(scene).run()
    built_in = musclefem.Scene(str(CUBE)).run()
    # The same Newton iterations under plain Newton (the tangent by central differences
    # is good enough for the implicit solver's convergence) and the same reaction to
    # round-off.
    plain_ours = musclefem.Scene.from_dict(plain_newton(scene)).run()
    plain_built_in = musclefem.Scene.from_dict(plain_newton(cube_dict())).run()
    np.testing.assert_array_equal(
        plain_ours["newton_iterations"], plain_built_in["newton_iterations"]
    )
    np.testing.assert_allclose(
        ours["reaction_cube.x1.x_n"], built_in["reaction_cube.x1.x_n"], rtol=1e-10
    )
    # Every element's stress, to 1e-9 of the largest (the lateral ones are round-off).
    stress = built_in.frames[-1]["cauchy_stress"]
    np.testing.assert_allclose(
        ours.frames[-1]["cauchy_stress"], stress, rtol=0, atol=1e-9 * np.abs(stress).max()
    )


def test_state_variables_go_in_and_out_and_reach_the_frames():
    def stiffening(F, fiber, state, params, **_):
        """neo-Hookean, its state the largest fiber stretch so far."""
        stretch = np.linalg.norm(np.einsum("pij,pj->pi", F, fiber), axis=1)
        return neo_hookean(F, params), np.maximum(state[:, 0], stretch)[:, None]

    musclefem.register_material(
        "numpy-stretch-memory",
        stiffening,
        {"mu": 1e4, "D": 2e-5},
        state={"largest_stretch": 1.0},
    )
    scene = cube_dict(divisions=(2, 2, 2))
    scene["materials"][0]["model"] = "numpy-stretch-memory"
    last = musclefem.Scene.from_dict(scene).run().frames[-1]
    # The cube's fibers run along x (the default), which it stretches to 1.5.
    np.testing.assert_allclose(last["state_largest_stretch"], 1.5, rtol=1e-9)
    np.testing.assert_allclose(last["fiber_stretch"], 1.5, rtol=1e-9)


def test_a_failing_law_is_a_musclefem_error_naming_the_material():
    def broken(F, **_):
        raise ValueError("no stress today")

    musclefem.register_material("numpy-broken", broken, {"mu": 1e4})
    with pytest.raises(
        musclefem.MusclefemError,
        match=r"material 'numpy-broken': its Python function .*broken failed: "
        r"ValueError: no stress today",
    ):
        musclefem.MaterialPoint("numpy-broken").uniaxial([0.0, 1.0], [1.0, 1.1])
    scene = cube_dict(divisions=(2, 2, 2))
    scene["materials"][0] = {"name": "rubber", "model": "numpy-broken"}
    with pytest.raises(musclefem.MusclefemError, match="numpy-broken.*no stress today"):
        musclefem.Scene.from_dict(scene).run()

    musclefem.register_material("numpy-flat", lambda F, **_: np.zeros((len(F), 6)))
    with pytest.raises(musclefem.MusclefemError, match=r"shape \[\d+, 6\], expected \[\d+, 3, 3\]"):
        musclefem.MaterialPoint("numpy-flat").uniaxial([0.0, 1.0], [1.0, 1.1])
    musclefem.register_material("numpy-stateless", neo_hookean, {"mu": 1e4, "D": 2e-5},
                                state=["s"])
    with pytest.raises(musclefem.MusclefemError, match="returned no state"):
        musclefem.MaterialPoint("numpy-stateless").uniaxial([0.0, 1.0], [1.0, 1.1])


def test_registration_is_checked():
    with pytest.raises(musclefem.MusclefemError, match="already registered"):
        musclefem.register_material("neo-hookean", neo_hookean)
    with pytest.raises(musclefem.MusclefemError, match="must be a function"):
        musclefem.register_material("numpy-x", 3.0)
    with pytest.raises(musclefem.MusclefemError, match=r"default -1 is outside its range \[0, inf\)"):
        musclefem.register_material("numpy-x", neo_hookean, {"mu": {"default": -1.0, "lower": 0.0}})
    with pytest.raises(musclefem.MusclefemError, match="unknown field 'units'"):
        musclefem.register_material("numpy-x", neo_hookean, {"mu": {"units": "Pa"}})
    # A parameter without default must be given; one out of its range is refused.
    musclefem.register_material("numpy-required", neo_hookean, {"mu": None, "D": 2e-5})
    with pytest.raises(musclefem.MusclefemError, match="'mu' has no default"):
        musclefem.MaterialPoint("numpy-required")
    musclefem.MaterialPoint("numpy-required", mu=1e4)
