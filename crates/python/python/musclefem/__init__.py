"""musclefem: continuum simulation of active skeletal muscle, from Python.

- ``materials()``: the material library, with every parameter's unit, default and range;
- ``MaterialPoint(name, **params).uniaxial(times, stretches, dt)``: one material point in
  uniaxial stress along its fiber;
- ``Scene.from_toml(path)`` / ``Scene.from_dict(scene, base_dir)``: a scene
  (docs/scene-format.md), checked on reading; ``.check()``, ``.describe()``, and
  ``.run(out=None, threads=None, progress=False)``, in memory or into a run directory,
  returning a ``Result`` (history, frames, mesh, ``write_vtu``);
- ``elongate(mode, shape, grips, ...)``: the single-muscle elongation test's curve;
- ``fibers(mesh, inlet, outlet)``: fiber directions of a mesh from the flow solver;
- ``fit(data, params, ...)``: ``musclefem fit``, material parameters fitted to a curve;
- ``knee(...)``: ``musclefem knee``, the squat's peak stresses and tendon tables;
- ``register_material(name, update, parameters, state)``: a material defined in Python
  (slow: one call per block of points), for material points and scenes.

Results are NumPy arrays named as the CSV columns (units in the names); errors are
``MusclefemError`` with the command line's message (file, line, key, element, time).
See docs/python.md.
"""

import collections.abc

from ._musclefem import (
    MaterialPoint,
    MusclefemError,
    Result,
    Scene,
    __version__,
    elongate,
    fibers,
    fit,
    knee,
    materials,
    register_material,
)

# A Result reads as the mapping of its history's columns (result["time_s"]).
collections.abc.Mapping.register(Result)

__all__ = [
    "MaterialPoint",
    "MusclefemError",
    "Result",
    "Scene",
    "__version__",
    "elongate",
    "fibers",
    "fit",
    "knee",
    "materials",
    "register_material",
]
