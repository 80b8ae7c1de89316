"""The type stubs (.pyi) name exactly what the package exports, and every export has a docstring."""

import ast
import pathlib

import pytest

import cgamesh
from cgamesh import cga

PACKAGE = pathlib.Path(__file__).resolve().parents[1] / "cgamesh"


@pytest.mark.parametrize("module, stub", [(cgamesh, "__init__.pyi"), (cga, "cga.pyi")])
def test_stubs_match_exports(module, stub):
    tree = ast.parse((PACKAGE / stub).read_text())
    names = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    names |= {n.target.id for n in tree.body if isinstance(n, ast.AnnAssign)}
    names -= {"ArrayLike", "Edit", "__version__"}
    assert names == set(module.__all__) - {"cga"}


@pytest.mark.parametrize("module", [cgamesh, cga])
def test_exports_are_documented(module):
    for name in module.__all__:
        obj = getattr(module, name)
        if callable(obj) and not isinstance(obj, cga.Multivector):
            assert (obj.__doc__ or "").strip(), name
