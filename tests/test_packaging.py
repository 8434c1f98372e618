"""A built wheel carries the bundled data: terrains, robot specs and URDFs load through the installed copy.

The wheel is built from this checkout (``pip wheel --no-build-isolation``), installed with ``pip install
--target`` into a temporary folder and imported from there (``PYTHONPATH``) by a fresh interpreter that
does not see the checkout; the test checks ``climb_ompl.__file__`` to be sure.  The file lists are globs,
so the test grows as robots and terrains are added.
"""

from __future__ import annotations

import json
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from conftest import ROOT

from climb_ompl.resources import robots_dir, terrains_dir, urdf_dir

CHILD = r"""
import json, sys
from pathlib import Path
import climb_ompl
from climb_ompl.resources import robots_dir, urdf_dir, terrains_dir
from climb_ompl.model.terrain import Terrain, bundled_terrains
out = {"file": climb_ompl.__file__, "robots_dir": str(robots_dir()), "urdf_dir": str(urdf_dir()),
       "terrains": {}, "robots": {}, "urdf": {}, "py_typed": (Path(climb_ompl.__file__).parent / "py.typed").exists()}
for name in bundled_terrains():
    t = Terrain.load(name)
    out["terrains"][name] = [t.source, t.content_hash()]
import pinocchio as pin
for f in sorted(urdf_dir().glob("*.urdf")):
    out["urdf"][f.name] = pin.buildModelFromUrdf(str(f)).nq
try:
    from climb_ompl.model.robot import RobotModel
except ImportError:
    RobotModel = None
for f in sorted(robots_dir().glob("*.yaml")):
    if RobotModel is None:
        out["robots"][f.stem] = None
        continue
    r = RobotModel.load(f.stem)
    out["robots"][f.stem] = [str(r.spec_path), str(r.urdf_path), r.nq, r.spec.get("urdf_package")]
print("RESULT" + json.dumps(out))
"""


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The package built as a wheel and installed into a temporary folder; returns that folder."""
    tmp = tmp_path_factory.mktemp("wheel")
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w",
                    str(tmp / "dist"), str(ROOT)], check=True, timeout=300, capture_output=True)
    wheels = list((tmp / "dist").glob("climb_ompl-*.whl"))
    assert len(wheels) == 1
    subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "-q", "--target", str(tmp / "site"),
                    str(wheels[0])], check=True, timeout=300, capture_output=True)
    return tmp


@pytest.mark.heavy
def test_wheel_contents(installed: Path) -> None:
    (wheel,) = (installed / "dist").glob("*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    for f in terrains_dir().glob("*.yaml"):
        assert f"climb_ompl/terrains/{f.name}" in names
    for folder, sub in ((robots_dir(), "robots"), (urdf_dir(), "urdf")):
        for f in folder.iterdir():
            if f.is_file():
                assert f"climb_ompl/_data/{sub}/{f.name}" in names, f"{sub}/{f.name} missing from the wheel"
    assert "climb_ompl/py.typed" in names
    pkg = ROOT / "climb_ompl"
    for f in pkg.rglob("*"):  # every source and data file of the package (schemas, trees, ...)
        if f.is_file() and "__pycache__" not in f.parts and not f.name.startswith("."):
            assert f"climb_ompl/{f.relative_to(pkg).as_posix()}" in names, f"{f} missing from the wheel"
    assert not any("__pycache__" in n or n.endswith(".pyc") for n in names)
    entry = next(n for n in names if n.endswith("entry_points.txt"))
    assert "climb-ompl = climb_ompl.cli:main" in zipfile.ZipFile(wheel).read(entry).decode()


@pytest.mark.heavy
def test_installed_package_loads_every_bundled_file(installed: Path, tmp_path: Path) -> None:
    site = installed / "site"
    proc = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, timeout=300,
                          cwd=tmp_path, env={"PYTHONPATH": str(site), "PATH": "/usr/bin:/bin"})
    assert proc.returncode == 0, proc.stderr[-2000:]
    res = json.loads(proc.stdout.split("RESULT", 1)[1])
    assert Path(res["file"]).is_relative_to(site), res["file"]
    assert Path(res["robots_dir"]).is_relative_to(site) and Path(res["urdf_dir"]).is_relative_to(site)
    assert res["py_typed"]
    assert sorted(res["terrains"]) == sorted(p.stem for p in terrains_dir().glob("*.yaml"))
    from climb_ompl.model.terrain import Terrain

    for name, (source, digest) in res["terrains"].items():
        assert Path(source).is_relative_to(site)
        assert digest == Terrain.load(name).content_hash()  # same content as the checkout's
    assert sorted(res["urdf"]) == sorted(p.name for p in urdf_dir().glob("*.urdf"))
    assert all(nq > 0 for nq in res["urdf"].values())
    assert sorted(res["robots"]) == sorted(p.stem for p in robots_dir().glob("*.yaml"))
    for name, info in res["robots"].items():
        if info is not None:
            spec, urdf, nq, package = info
            assert Path(spec).is_relative_to(site), (name, spec)
            # bundled URDFs ship in the wheel; a third-party robot's is read from its package (urdf_package)
            assert Path(urdf).is_relative_to(site) or (package and package in urdf), (name, urdf)


def test_checkout_finds_the_data_too() -> None:
    """From a source checkout / editable install, robots/ and urdf/ are the top-level folders."""
    import climb_ompl

    pkg = Path(climb_ompl.__file__).resolve().parent
    if (pkg / "_data").is_dir():  # pragma: no cover - running from an installed wheel
        pytest.skip("running from an installed wheel")
    assert robots_dir() == ROOT / "robots" and urdf_dir() == ROOT / "urdf"
    assert terrains_dir() == ROOT / "climb_ompl" / "terrains"
