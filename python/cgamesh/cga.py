"""The algebra G(4,1) of conformal geometric algebra (cgamesh's C++ cga library).

Basis and blade order
---------------------
A :class:`Multivector` holds 32 float64 coefficients (``.value``) over the *null* basis
``e1 e2 e3 einf eo`` of the paper (``einf·eo = -1``, ``einf² = eo² = 0``). Blade ``b`` (0 … 31)
is the outer product of the basis vectors whose bits are set in ``b`` — bit 0 ``e1``, bit 1
``e2``, bit 2 ``e3``, bit 3 ``einf``, bit 4 ``eo`` — in increasing bit order: blade 3 is
``e1^e2``, blade 24 ``einf^eo``, blade 31 ``I = e1^e2^e3^einf^eo``. ``blade_names`` lists them.

The ``clifford`` package's ``conformalize(Cl(3))`` layout uses the orthonormal basis
``e1 e2 e3 e4 e5`` with ``e4 = e+`` (square +1) and ``e5 = e-`` (square -1), and blades in order
of grade, then lexicographic (``1, e1, …, e5, e12, e13, …, e45, e123, …, e12345``;
``clifford_blade_names``). The two are related by

    einf = e4 + e5,      eo = (e5 - e4) / 2,      e4 = einf/2 - eo,      e5 = einf/2 + eo,

so ``einf^eo = e4^e5`` and a point ``up(x) = x + ½|x|² einf + eo`` has clifford coefficients
``e4 = ½|x|² - ½`` and ``e5 = ½|x|² + ½``. :func:`to_clifford` and :func:`from_clifford` convert
coefficient arrays (``(32,)`` or ``(N, 32)``) between the two layouts; the pseudoscalar
``e1^e2^e3^einf^eo`` equals clifford's ``e12345``.

Operators: ``*`` geometric, ``^`` outer, ``|`` inner (Hestenes: grade ``|ga - gb|``, zero when
a factor is a scalar), ``<<`` left and ``>>`` right contraction, ``~`` reverse. When porting
code, check that clifford's operator of the same symbol is the same product for the grades
involved (its ``|`` and contractions differ from Hestenes' on scalars).

Batched forms: :func:`up`, :func:`down` and :func:`sandwich` take ``(N, 3)`` / ``(N, 32)`` arrays
and loop in C++ with the GIL released.
"""

from ._cgamesh.cga import (
    I,
    Multivector,
    blade,
    blade_names,
    clifford_blade_names,
    dilator,
    down,
    e1,
    e2,
    e3,
    e4,
    e5,
    einf,
    eo,
    exp,
    from_clifford,
    lerp,
    log,
    log_blend,
    plane,
    rotor,
    sandwich,
    sphere,
    to_clifford,
    translator,
    up,
)

__all__ = [
    "I",
    "Multivector",
    "blade",
    "blade_names",
    "clifford_blade_names",
    "dilator",
    "down",
    "e1",
    "e2",
    "e3",
    "e4",
    "e5",
    "einf",
    "eo",
    "exp",
    "from_clifford",
    "lerp",
    "log",
    "log_blend",
    "plane",
    "rotor",
    "sandwich",
    "sphere",
    "to_clifford",
    "translator",
    "up",
]
