"""numba's on-disk cache of armanim's compiled functions is kept only while every compiled
module is unchanged (:func:`armanim.arm.kernel.stamp_cache`): numba itself watches a function's
own file only, while its machine code holds the compiled functions it calls from other files."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from armanim.arm import kernel

SRC = Path(kernel.__file__).resolve().parents[1]

CALLEE = "import numba\n\n@numba.njit(cache=True)\ndef value():\n    return {value}.0\n"
CALLER = textwrap.dedent("""
    import sys
    import numba
    from callee import value
    from armanim.arm.kernel import sources_stamp, stamp_cache

    @numba.njit(cache=True)
    def read():
        return value()

    if sys.argv[1] == "stamped":
        stamp_cache(read, sources_stamp(("callee.py", "caller.py"), root={root!r}))
    print(read())
""")


def _read(folder: Path, mode: str) -> str:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(folder / "cache"), "PYTHONPATH": str(folder)}
    proc = subprocess.run(
        [sys.executable, str(folder / "caller.py"), mode], capture_output=True, text=True, env=env, timeout=300
    )
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.strip()


@pytest.mark.parametrize("mode, after_the_edit", [("numba's own", "1.0"), ("stamped", "2.0")])
def test_an_edit_of_a_callee_in_another_module_reaches_the_cached_caller(tmp_path, mode, after_the_edit):
    (tmp_path / "callee.py").write_text(CALLEE.format(value=1))
    (tmp_path / "caller.py").write_text(CALLER.format(root=str(tmp_path)))
    assert _read(tmp_path, mode) == "1.0"  # compiled and cached
    time.sleep(0.01)  # a later mtime, whatever the file system's resolution
    (tmp_path / "callee.py").write_text(CALLEE.format(value=2))  # the same size: only the mtime tells
    # numba's own stamp (the caller's file) still matches: it runs the cached, stale machine code;
    # stamped with both files, the caller compiles again and calls the new callee
    assert _read(tmp_path, mode) == after_the_edit


def test_every_module_that_defines_compiled_functions_is_in_the_stamp():
    defining = {str(p.relative_to(SRC)) for p in SRC.rglob("*.py") if re.search(r"^@compiled\(", p.read_text(), re.M)}
    assert defining and defining == set(kernel.COMPILED_MODULES)


def test_a_compiled_function_carries_the_stamp_of_every_compiled_module():
    stamp = kernel._forward_one._cache._cache_file._source_stamp  # numba's index stamp of a kernel function
    assert stamp[1] == kernel.sources_stamp(kernel.COMPILED_MODULES)
    assert [entry[0] for entry in stamp[1]] == list(kernel.COMPILED_MODULES) and all(len(e) == 3 for e in stamp[1])
