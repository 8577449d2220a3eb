"""The type stubs (__init__.pyi) name every public function, class and method the package has."""
import ast
import inspect
import pathlib

import octray


def stub_names():
    tree = ast.parse((pathlib.Path(octray.__file__).parent / "__init__.pyi").read_text())
    top, scene = set(), set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            top.add(node.name)
        if isinstance(node, ast.ClassDef) and node.name == "Scene":
            scene = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
    return top, scene


def test_stubs_cover_the_api():
    top, scene = stub_names()
    assert set(octray.__all__) <= top
    public = {n for n, v in vars(octray.Scene).items()
              if not n.startswith("_") and (callable(v) or isinstance(v, (property, classmethod)))}
    assert public | {"__init__"} == scene
    for name in octray.__all__:
        assert inspect.getdoc(getattr(octray, name)), name
    for name in public:
        assert inspect.getdoc(getattr(octray.Scene, name)), name
