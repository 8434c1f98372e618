"""The reach prefilters of :mod:`climb_ompl.reach` against configurations built to touch their bounds."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from climb_ompl.reach import pair_reach
from climb_ompl.robot import RobotModel

ROOT = Path(__file__).resolve().parents[1]


def planar(radius: float | None) -> RobotModel:
    """The planar three-limbed robot, with sphere feet of ``radius`` (``None``: its point contacts)."""
    spec = yaml.safe_load((ROOT / "robots" / "planar-3limb.yaml").read_text())
    if radius is not None:
        for lb in spec["limbs"]:
            lb["contact"] = {"type": "sphere", "radius": radius}
    return RobotModel.from_spec(spec, base_dir=ROOT / "urdf")


@pytest.mark.parametrize("radius", [None, 0.02, 0.05])
def test_pair_reach_bounds_two_holds_touched_at_full_stretch(radius):
    """Limbs 1 and 2 stretched straight in opposite directions (their shoulders meet at the pelvis): the hands are
    the two reaches apart, and two holds whose normals face each other put those hand frames (sphere centres)
    there from ``r`` farther out each.  The prefilter must keep such a pair: the hold distance is at most
    ``pair_reach``, equal to it at full stretch (a prefilter ignoring the radius cuts it by ``2 r``)."""
    r = planar(radius)
    q = np.asarray(r.nominal_q, dtype=float)
    names = list(r.joint_names)
    for j in ("limb1_elbow", "limb2_elbow", "base_theta"):
        q[names.index(j)] = 0.0
    q[names.index("limb1_shoulder")], q[names.index("limb2_shoulder")] = np.pi, 0.0
    ha, hb = r.hand_position(q, "limb1"), r.hand_position(q, "limb2")
    span = float(np.linalg.norm(ha - hb))
    assert span == pytest.approx(r.limb("limb1").reach + r.limb("limb2").reach, abs=1e-9)  # fully stretched
    u = (ha - hb) / span
    rad = radius or 0.0
    pa, pb = ha + rad * u, hb - rad * u  # holds facing each other: normals -u and u
    for limb, p, n, h in (("limb1", pa, -u, ha), ("limb2", pb, u, hb)):
        assert np.allclose(r.limb(limb).contact.hand_target(p, n), h)
    assert float(np.linalg.norm(pa - pb)) == pytest.approx(pair_reach(r)[("limb1", "limb2")], abs=1e-9)
