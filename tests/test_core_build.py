"""The install's choice of core (build_support/core_build.py): compiled where asked, or by
default where the machine can build C extensions; Python where asked, in an editable
install, or where compiling fails, with nothing half built left behind."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest
from setuptools import Distribution, Extension

ROOT = Path(__file__).resolve().parents[1]
# (the build's own module, which setup.py and the build backend import; no package's)
_spec = importlib.util.spec_from_file_location("core_build",
                                               ROOT / "build_support" / "core_build.py")
assert _spec is not None and _spec.loader is not None
core_build = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(core_build)


@pytest.fixture
def headers(tmp_path, monkeypatch):
    """Python's headers in a folder of the test's (Python.h there or not, as it makes)."""
    folder = tmp_path / "include"
    folder.mkdir()
    real = core_build.sysconfig.get_path
    monkeypatch.setattr(core_build.sysconfig, "get_path",
                        lambda name: str(folder) if name == "include" else real(name))
    return folder


@pytest.mark.parametrize("value", ["yes", "true", "2", " 1"])
def test_a_value_other_than_1_0_or_unset_is_refused_in_one_line(monkeypatch, value):
    monkeypatch.setenv("INVADERS_COMPILE", value)
    with pytest.raises(SystemExit) as refused:
        core_build.compiling()
    said = str(refused.value)
    assert said.startswith(f"INVADERS_COMPILE={value!r}: 1 (") and "\n" not in said


def test_unset_compiles_exactly_where_a_compiler_and_pythons_headers_are(monkeypatch, headers):
    monkeypatch.delenv("INVADERS_COMPILE", raising=False)
    monkeypatch.setenv("CC", f"{sys.executable} -pthread")  # (a program that is there)
    assert not core_build.compiling()  # no Python.h
    (headers / "Python.h").write_text("")
    assert core_build.compiling()
    monkeypatch.setenv("CC", "/nowhere/cc -pthread")
    assert not core_build.compiling()
    monkeypatch.setenv("CC", " ")
    assert not core_build.compiling()


def test_1_compiles_and_0_does_not_whatever_the_machine(monkeypatch, headers):
    monkeypatch.setenv("CC", "/nowhere/cc")
    monkeypatch.setenv("INVADERS_COMPILE", "1")
    assert core_build.compiling()
    monkeypatch.setenv("CC", sys.executable)
    (headers / "Python.h").write_text("")
    monkeypatch.setenv("INVADERS_COMPILE", "0")
    assert not core_build.compiling()


def test_an_editable_install_stays_python_and_refuses_1_in_one_line(monkeypatch, headers):
    monkeypatch.setenv("CC", sys.executable)
    (headers / "Python.h").write_text("")
    monkeypatch.delenv("INVADERS_COMPILE", raising=False)
    assert core_build.compiling() and not core_build.compiling(editable=True)
    monkeypatch.setenv("INVADERS_COMPILE", "1")
    with pytest.raises(SystemExit) as refused:
        core_build.compiling(editable=True)
    said = str(refused.value)
    assert said.startswith("INVADERS_COMPILE=1: an editable install (-e) stays Python")
    assert "\n" not in said


def _build(folder: Path, sources: dict[str, str]) -> list[Path]:
    """Extensions of one C file each (name: source), built by the fallback build as a
    wheel's are (into a folder of the build's, `lib`, which the wheel takes whole); what
    is there after it."""
    extensions = []
    for name, code in sources.items():
        (folder / f"{name}.c").write_text(code)
        extensions.append(Extension(name, [f"{name}.c"]))
    dist = Distribution({"name": "probe", "ext_modules": extensions,
                         "cmdclass": {"build_ext": core_build.FallbackBuild}})
    command = dist.get_command_obj("build_ext")
    command.build_lib, command.build_temp = str(folder / "lib"), str(folder / "temp")
    dist.run_command("build_ext")
    return sorted((folder / "lib").glob("*"))


GOOD = """#include <Python.h>
static struct PyModuleDef m = {PyModuleDef_HEAD_INIT, "good", NULL, -1, NULL};
PyMODINIT_FUNC PyInit_good(void) { return PyModule_Create(&m); }
"""


@pytest.mark.skipif(not core_build.can_compile(), reason="no C compiler or Python headers")
def test_a_failed_compile_leaves_nothing_built_and_says_the_core_is_python(tmp_path,
                                                                          monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (built,) = _build(tmp_path, {"good": GOOD})
    assert built.name.startswith("good.") and not capsys.readouterr().err.count("invaders:")
    built.unlink()
    # the first extension built, the second failing: the first is taken away again
    assert _build(tmp_path, {"good": GOOD, "bad": "this is not C;\n"}) == []
    (said,) = [line for line in capsys.readouterr().err.splitlines()
               if line.startswith("invaders:")]
    assert said.startswith("invaders: the core is installed as Python: compiling it failed (")


def test_without_the_compiler_the_build_says_the_core_is_python(tmp_path, monkeypatch,
                                                                capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("CC", "/nowhere/cc")
    monkeypatch.setenv("LDSHARED", "/nowhere/cc -shared")
    assert _build(tmp_path, {"good": GOOD}) == []
    assert "invaders: the core is installed as Python: compiling it failed (" in (
        capsys.readouterr().err)
