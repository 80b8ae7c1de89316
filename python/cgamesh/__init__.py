"""cgamesh: Conformal Geometric Algebra animation, surgery and deformation of rigged 3D models.

A thin front end over the C++ library (the same functions the ``cgamesh`` command line calls,
so results equal the CLI's). Arrays go in and out as numpy arrays:

- ``load(path)`` -> :class:`Model` (``meshes``, ``skeleton``, ``clips``, ``warnings``,
  ``info()``, ``save()``, ``pose()``, ``skin()``, ``animate()``)
- surgery: :func:`cut`, :func:`tear`, :func:`drill` -> :class:`SurgeryResult`;
  :class:`LiveModel` for edits in place, :class:`Tissue` for living tissue on it (wounds that open
  under the skin's tension and keep animating)
- deformation: :func:`deform`, :class:`Deformer` (the JSON spec of ``cgamesh deform``),
  :func:`harmonic_field`, :class:`MotorBlend`, :func:`fabrik`, :func:`fit_bspline_motors`
- :mod:`cgamesh.cga`: multivectors of G(4,1)

Errors are raised as :class:`Error` and its subclasses :class:`InvalidInputError` (with
:class:`FileError` below it), :class:`WriteError`, :class:`TopologyError`, :class:`SolverError`
and :class:`PlatformError`, carrying the library's message.

Memory: ``Mesh`` arrays are read-only views of the model (no copy; they keep it alive);
``skin()``, ``deform()`` and ``Deformer.apply()`` return arrays that own their memory (no copy
of the C++ result); arguments are used in place when they are C-contiguous float64 (or int32
for ids) and copied otherwise. Long calls release the GIL.
"""

from . import _cgamesh
from ._cgamesh import (
    Clip,
    Deformer,
    Error,
    FileError,
    HarmonicField,
    InvalidInputError,
    LiveModel,
    Mesh,
    Model,
    MorphTarget,
    MotorBlend,
    PlatformError,
    Pose,
    Skeleton,
    SolverError,
    SurgeryResult,
    Tissue,
    TopologyError,
    WriteError,
    cut,
    deform,
    drill,
    fabrik,
    fit_bspline_motors,
    harmonic_field,
    load,
    tear,
)
from . import cga

__all__ = [
    "Clip",
    "Deformer",
    "Error",
    "FileError",
    "HarmonicField",
    "InvalidInputError",
    "LiveModel",
    "Mesh",
    "Model",
    "MorphTarget",
    "MotorBlend",
    "PlatformError",
    "Pose",
    "Skeleton",
    "SolverError",
    "SurgeryResult",
    "Tissue",
    "TopologyError",
    "WriteError",
    "cga",
    "cut",
    "deform",
    "drill",
    "fabrik",
    "fit_bspline_motors",
    "harmonic_field",
    "load",
    "tear",
]

__version__ = "0.1.0"
del _cgamesh
