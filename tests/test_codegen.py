"""One cache root for every engine's generated kernels ($CRAQUELURE_CACHE)."""

from __future__ import annotations

from craquelure import codegen


def test_generated_dir_is_a_subfolder_of_the_cache_root(tmp_path, monkeypatch):
    monkeypatch.setenv("CRAQUELURE_CACHE", str(tmp_path / "root"))
    path = codegen.generated_dir("sph")
    assert path == tmp_path / "root" / "sph"
    assert path.is_dir()


def test_import_generated_writes_atomically_and_imports(tmp_path):
    path = tmp_path / "mod_a.py"
    module = codegen.import_generated("VALUE = 42\n", "craquelure_test_generated_a", path)
    assert module.VALUE == 42
    assert path.read_text() == "VALUE = 42\n"
    assert [p.name for p in tmp_path.iterdir()] == ["mod_a.py"]  # no temporary file left
