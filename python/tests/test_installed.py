"""tools/check's pip stage (OCTRAY_INSTALLED_PREFIX set): the tests run against the package
`pip install .` put in that venv, whole (stubs, py.typed, metadata), not against a build tree.
The README's Python example, everywhere."""
import importlib.metadata
import os
import pathlib
import re
import subprocess
import sys

import pytest

import octray
from conftest import SOURCE

PREFIX = os.environ.get("OCTRAY_INSTALLED_PREFIX", "")


@pytest.mark.skipif(not PREFIX, reason="not tools/check's pip stage (OCTRAY_INSTALLED_PREFIX unset)")
def test_the_package_under_test_is_the_installed_one():
    package = pathlib.Path(octray.__file__).resolve().parent
    assert pathlib.Path(sys.prefix).resolve() == pathlib.Path(PREFIX).resolve()
    assert pathlib.Path(PREFIX).resolve() in package.parents, package
    assert package.name == "octray" and package.parent.name == "site-packages"
    assert (package / "__init__.pyi").is_file() and (package / "py.typed").is_file()
    assert list(package.glob("_octray*.so"))
    assert importlib.metadata.version("octray") == octray.__version__


def test_the_readmes_python_example_prints_what_it_says():
    readme = (SOURCE / "README.md").read_text()
    section = readme[readme.index("## Python"):readme.index("\n## ", readme.index("## Python") + 1)]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    assert len(code.strip().splitlines()) == 5
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=dict(os.environ))
    assert r.returncode == 0, r.stderr
    promised = re.search(r"# (\[.*?\]\]?)(:|$)", code.strip().splitlines()[-1]).group(1)
    assert r.stdout.strip() == promised, (r.stdout, promised)
