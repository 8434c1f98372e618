"""MRWALLSPECT III's 35-degree hill climbed up and down as one chained sequence (Kim, Kang & Choi, Fig. 12-15):
each transition starts in the posture the previous one ended in, its feet stay on the hill, and every transition
plan passes the independent verifier."""

from __future__ import annotations

import json
import math
from functools import lru_cache

import numpy as np
import pytest

from climb_ompl.errors import InputError
from climb_ompl.mrwallspect.chain import hill, next_start, plan_chain
from climb_ompl.mrwallspect.slope import plan_slope
from climb_ompl.verification import verify_plan_dict

ANGLE, LENGTH = 35.0, 0.7  # slope angle, length of the up slope, the top and the down slope (m)


@lru_cache(maxsize=1)
def chain():
    return plan_chain(*hill(ANGLE, LENGTH, LENGTH, LENGTH))


def _hill_profile() -> np.ndarray:
    """The hill's corners in the first transition's frame (x forward, z up), from the angle and lengths alone."""
    a = math.radians(ANGLE)
    up = np.array([math.cos(a), math.sin(a)]) * LENGTH
    return np.array([[-2.0, 0.0], [0.0, 0.0], up, up + [LENGTH, 0.0], up + [LENGTH + up[0], -up[1]],
                     [2 * up[0] + LENGTH + 2.0, 0.0]])


def _distance_to_profile(p: np.ndarray, corners: np.ndarray) -> float:
    out = math.inf
    for a, b in zip(corners[:-1], corners[1:], strict=True):
        s = float(np.clip((p - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0))
        out = min(out, float(np.linalg.norm(p - (a + s * (b - a)))))
    return out


@pytest.mark.heavy
def test_hill_is_found_as_four_chained_transitions():
    ch = chain()
    assert ch.found, ch.reason
    assert [r.plan["query"]["kind"] for r in ch.results] == ["concave", "convex", "convex", "concave"]
    assert "start_q" not in ch.results[0].plan["query"]  # the first starts in the robot's basic form
    for a, b, length in zip(ch.results[:-1], ch.results[1:], ch.lengths, strict=True):
        # continuity: the next transition's first frame is the previous one's last posture, carried over the plane
        q_end = next_start(a.plan, length)
        assert np.allclose(b.plan["frames"][0]["q"], q_end, atol=1e-9)
        assert np.allclose(b.plan["query"]["start_q"], q_end, atol=0)
        assert b.plan["frames"][0]["attached"] == [True] * 4 and b.plan["frames"][0]["plane"] == [1] * 4


@pytest.mark.heavy
def test_chained_transitions_share_one_world():
    """Mapped into the first transition's frame, gravity is the same in every transition, the last feet of one
    transition are the first feet of the next, and every attached foot is on the hill's surface."""
    ch = chain()
    corners = _hill_profile()
    frames = ch.world_frames()
    prev_feet = None
    for res, (R, c) in zip(ch.results, frames, strict=True):
        assert np.allclose(R @ np.asarray(res.plan["gravity"]), [0.0, 0.0, -9.81], atol=1e-9)
        feet = [np.array([c + R @ np.asarray(p) for p in f["feet"]]) for f in res.plan["frames"]]
        if prev_feet is not None:
            assert np.allclose(feet[0], prev_feet, atol=1e-9)
        prev_feet = feet[-1]
        for f, w in zip(res.plan["frames"], feet, strict=True):
            for j in np.flatnonzero(f["attached"]):
                assert _distance_to_profile(w[j, [0, 2]], corners) < 1e-6
    # the robot ends on the floor beyond the hill, the whole hill crossed
    last = frames[-1][1] + frames[-1][0] @ np.asarray(ch.results[-1].plan["frames"][-1]["body"]["origin"])
    assert last[0] > corners[4, 0] and abs(last[2] - (ch.results[-1].plan["trajectory"]["h"]
                                                       + ch.results[-1].plan["trajectory"]["h_f"])) < 1e-6


@pytest.mark.heavy
def test_every_chained_transition_verifies():
    for res in chain().results:
        rep = verify_plan_dict(json.loads(json.dumps(res.plan)), "<chain>", resolution=0.05)
        assert rep.ok, [str(v) for v in rep.violations]


@pytest.mark.heavy
def test_verifier_catches_a_start_posture_the_plan_does_not_start_from():
    p = json.loads(json.dumps(chain().results[1].plan))
    p["query"]["start_q"][3] += 0.01
    rep = verify_plan_dict(p, "<chain>", resolution=0.5)
    assert rep.by_check().get("integrity") == 1


def test_too_short_a_slope_is_infeasible_with_the_reason():
    ch = plan_chain(*hill(ANGLE, 0.5, 0.5, 0.5))
    assert not ch.found and len(ch.results) == 2
    assert "transition 2 (convex)" in ch.reason and "past the body pose where the transition begins" in ch.reason


@pytest.mark.heavy
def test_bad_start_and_lengths_are_input_errors():
    q = np.asarray(chain().results[1].plan["frames"][0]["q"])
    with pytest.raises(InputError, match="start_q"):
        plan_slope(ANGLE, "convex", start_q=q[:5])
    lifted = q.copy()
    lifted[1] += 0.05
    with pytest.raises(InputError, match="level on the first plane"):
        plan_slope(ANGLE, "convex", start_q=lifted)
    with pytest.raises(InputError, match="plane_lengths"):
        plan_slope(ANGLE, "convex", plane_lengths=(1.0, -1.0))
    with pytest.raises(InputError, match="lengths"):
        plan_chain(*hill(ANGLE)[:1], [1.0])
