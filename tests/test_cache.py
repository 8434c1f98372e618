"""The on-disk cache of reach maps: read back exactly, keyed by what the maps depend on, robust to a bad entry."""

from __future__ import annotations

import numpy as np
import pytest

from climb_ompl import cache
from climb_ompl.model import reach
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    """An empty cache folder and no maps kept in this process."""
    monkeypatch.setenv(cache.ENV, str(tmp_path / "cache"))
    monkeypatch.setattr(reach, "_REACH_MAPS", {})
    return tmp_path / "cache" / reach.CACHE_KIND


def _probed(monkeypatch) -> list[str]:
    calls: list[str] = []
    real = reach._reach_map

    def counting(robot, lb, normal, *a, **k):
        calls.append(lb.name)
        return real(robot, lb, normal, *a, **k)

    monkeypatch.setattr(reach, "_reach_map", counting)
    return calls


def _same(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(
        type(x) is type(y) and np.array_equal(x, y) for j in a for x, y in zip(a[j], b[j], strict=True))


def test_maps_read_back_from_disk_are_the_maps_probed(fresh, monkeypatch):
    robot, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    probed = _probed(monkeypatch)
    assert not reach.maps_kept(robot, wall)
    first = reach.reach_maps(robot, wall)
    assert sorted(probed) == sorted(lb.name for lb in robot.limbs) and len(list(fresh.glob("*.npz"))) == 1
    monkeypatch.setattr(reach, "_REACH_MAPS", {})  # a new process: only the disk remembers
    assert reach.maps_kept(robot, wall)
    probed.clear()
    again = reach.reach_maps(RobotModel.load("lemur"), wall)
    assert probed == [] and _same(first, again)


def test_a_changed_robot_or_wall_orientation_has_its_own_entry(fresh):
    robot = RobotModel.load("lemur")
    n = reach.wall_normal(Terrain.load("demo-wall"))
    key = reach.cache_key(robot, n)
    assert reach.cache_key(RobotModel.load("lemur"), n) == key  # the same inputs: the same entry
    assert reach.cache_key(robot, np.array([0.0, 0.6, 0.8])) != key
    j = robot.limbs[0].joint_indices[0]
    spec = {**robot.spec, "joint_limits": {robot.joint_names[j]: [float(robot.lower[j]) + 0.01, float(robot.upper[j])]}}
    narrower = RobotModel.from_spec(spec, base_dir=robot.urdf_path.parent.parent / "robots")
    assert reach.cache_key(narrower, n) != key


@pytest.mark.heavy
def test_an_unreadable_entry_is_probed_again_and_replaced(fresh, monkeypatch):
    robot, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    good = reach.reach_maps(robot, wall)
    (entry,) = fresh.glob("*.npz")
    entry.write_bytes(b"not a zip file")
    monkeypatch.setattr(reach, "_REACH_MAPS", {})
    probed = _probed(monkeypatch)
    assert _same(reach.reach_maps(robot, wall), good) and probed
    assert cache.load(reach.CACHE_KIND, entry.stem) is not None  # rewritten


@pytest.mark.parametrize("value", ["off", ""])
def test_the_cache_turned_off_writes_nothing(tmp_path, monkeypatch, value):
    monkeypatch.setenv(cache.ENV, value)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(reach, "_REACH_MAPS", {})
    assert cache.folder() is None
    reach.reach_maps(RobotModel.load("lemur"), Terrain.load("demo-wall"))
    assert not any(tmp_path.rglob("*.npz"))


def test_a_folder_that_cannot_be_written_keeps_nothing_and_does_not_fail(tmp_path, monkeypatch):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    monkeypatch.setenv(cache.ENV, str(blocker / "cache"))  # under a file: mkdir fails
    monkeypatch.setattr(reach, "_REACH_MAPS", {})
    assert reach.reach_maps(RobotModel.load("lemur"), Terrain.load("demo-wall"))
    assert cache.save("x", "y", {"a": np.zeros(1)}) is None


def test_the_default_folder_follows_xdg(monkeypatch, tmp_path):
    monkeypatch.delenv(cache.ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert cache.folder() == tmp_path / "climb_ompl"
    monkeypatch.delenv("XDG_CACHE_HOME")
    assert cache.folder() is not None and cache.folder().name == "climb_ompl"


def test_digest_parts_are_delimited():
    assert cache.digest("ab", "c") != cache.digest("a", "bc")
