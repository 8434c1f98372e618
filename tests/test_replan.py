"""Re-planning when a hold fails: the new plan keeps the executed steps, avoids the changed hold, records the
event and passes the independent verifier against the changed terrain; bad input is refused clearly."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from climb_ompl.climb.multistep import default_start, plan_climb
from climb_ompl.climb.replan import replan, resume_point, uses_holds
from climb_ompl.climb.status import ClimbStatus
from climb_ompl.errors import QueryError, TerrainError
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain
from climb_ompl.plan.events import TerrainChange
from climb_ompl.verification.climb import verify


@pytest.fixture(scope="module")
def climb():
    robot, wall = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    stance, q0 = default_start(robot, wall, seed=0)
    res = plan_climb(robot, wall, stance, 1.6, q_start=q0, time_limit=60, seed=0, keep_search=True)
    assert res.found, res.reason
    return robot, wall, res


def _next_grab(plan, k):
    return next(i for i in range(k, len(plan.steps)) if plan.steps[i].action == "grab")


@pytest.mark.climb
@pytest.mark.parametrize("warm", [True, False])
def test_removed_hold_replanned_and_verified(climb, warm):
    robot, wall, res = climb
    plan = res.plan
    k = 1
    hold = plan.steps[_next_grab(plan, k)].hold
    out = replan(plan, k, TerrainChange(remove=(hold,)), warm=res.search if warm else None, robot=robot)
    assert out.found, out.climb.reason
    new = out.plan
    assert new.steps[:out.resumed_at] == plan.steps[:out.resumed_at]  # executed steps kept as they were
    assert out.resumed_at == k and not out.backed_off
    runs = out.stats["searches"]  # every search the re-plan ran, the answering one last
    assert runs and all(r["search"] in ("rejoin", "goal", "scratch") and r["s"] >= 0 for r in runs)
    assert runs[-1]["found"] and sum(r["s"] + r.get("join_s", 0.0) for r in runs) <= out.stats["warm_s"] + \
        out.stats.get("scratch_s", 0.0) + 1e-6
    assert all(hold not in uses_holds(s) for s in new.steps[out.resumed_at:])
    assert hold not in new.terrain["data"]["holds"][0].values() and len(new.terrain["data"]["holds"]) == \
        len(wall.holds) - 1
    ev = new.events[-1]
    assert ev["type"] == "replan" and ev["at_step"] == k and ev["change"]["remove"] == [hold]
    assert ev["before"][hold]["position"] == wall.to_dict()["holds"][wall.hold_ids.index(hold)]["position"]
    rep = verify(new)
    assert rep.ok, [str(v) for v in rep.violations[:5]]


@pytest.mark.climb
def test_executed_steps_are_history_and_verify_on_the_terrain_before_the_change(climb):
    """A hold the robot used and left long ago fails: the executed steps are kept (they happened on the terrain
    as it was) and the new plan verifies, its kept steps on the terrain before the change (rebuilt from the
    event to its exact hash), its new ones on the changed terrain.  A back-off happens only when the state
    reached relies on the hold."""
    from climb_ompl.climb.replan import state_relies
    from climb_ompl.plan.events import terrain_before
    from climb_ompl.plan.file import sha256_json

    robot, wall, res = climb
    plan = res.plan
    k = len(plan.steps) - 1
    used = sorted(uses_holds(plan.steps[0]) - set(dict(plan.steps[k].stance).values()))
    assert used, "step 0 uses a hold the last step does not"
    change = TerrainChange(remove=(used[0],))
    assert not state_relies(plan, k, change.touched) and resume_point(plan, k, change.touched) == k
    out = replan(plan, k, change, robot=robot)
    assert out.found and out.resumed_at == k and not out.backed_off, out.climb.reason
    assert out.plan.steps[:k] == plan.steps[:k]
    ev = out.plan.events[-1]
    old = terrain_before(out.plan.terrain["data"], ev)
    assert old is not None and sha256_json({x: v for x, v in old.items() if x != "description"}) == \
        plan.terrain["sha256"] and old["holds"] == plan.terrain["data"]["holds"]
    rep = verify(out.plan)
    assert rep.ok, [str(v) for v in rep.violations[:5]]
    # the same kept steps checked on the changed terrain fail: the start stance holds the removed hold
    import dataclasses

    flat = dataclasses.replace(out.plan, events=())
    assert f"stance_change: unknown hold {used[0]!r}" in [str(v).split(": ", 1)[1] for v in verify(flat).violations]
    # a hand on the changed hold in the state reached: the re-plan backs off before the step that took it
    held = sorted(set(dict(plan.steps[k].stance).values()) - set(dict(plan.start_stance).values()))[0]
    first = resume_point(plan, k, frozenset({held}))
    assert first < k and not state_relies(plan, first, frozenset({held}))
    assert all(state_relies(plan, i, frozenset({held})) for i in range(first + 1, k + 1))


@pytest.mark.climb
def test_a_re_plan_event_that_does_not_explain_its_terrains_is_caught(climb):
    """``verify`` checks a re-planned plan's kept steps on the terrain before the change, which it rebuilds from
    the event: an event edited to claim another change, holds it does not alter, or no new step after it is
    caught (the oracle: the genuine event verifies; each edit is reported as an integrity violation, or the plan's
    end state fails on the terrain it embeds)."""
    import dataclasses

    robot, wall, res = climb
    plan = res.plan
    k = 1
    hold = plan.steps[_next_grab(plan, k)].hold
    out = replan(plan, k, TerrainChange(remove=(hold,)), robot=robot)
    assert out.found, out.climb.reason
    new, ev = out.plan, out.plan.events[-1]
    assert verify(new).ok

    def with_event(**kw):
        return dataclasses.replace(new, events=(*new.events[:-1], {**ev, **kw}))

    def checks(p):
        return [str(v) for v in verify(p).violations if v.check == "integrity"]

    assert any("events[0].change cannot be applied" in m for m in checks(with_event(change={})))
    assert any("events[0].before: expected" in m for m in checks(with_event(before=list(ev["before"].values()))))
    other = next(h for h in wall.hold_ids if h != hold)
    claimed = {**ev["change"], "remove": [other]}
    assert any("events[0].before records holds" in m for m in checks(with_event(change=claimed)))
    moved = {**ev["change"], "remove": [], "move": {hold: [0.0, 0.0]}}
    assert any("events[0].before records holds" in m or "does not give the terrain after it" in m
               for m in checks(with_event(change=moved)))
    late = verify(with_event(resumed_at_step=len(new.steps) + 1))
    assert any("resumed_at_step" in str(v) for v in late.violations)
    # an event consistent in itself, with no new step after it: the old plan whole, "a hold it ends on removed
    # after its last step"; the state the plan ends in must hold on the changed terrain too, and does not
    from climb_ompl.plan.file import sha256_json

    last = sorted(dict(plan.steps[-1].stance_after).values())[0]
    data = plan.terrain["data"]
    gone = {**data, "holds": [h for h in data["holds"] if h["id"] != last]}
    i = [h["id"] for h in data["holds"]].index(last)
    forged = {"type": "replan", "at_step": len(plan.steps), "resumed_at_step": len(plan.steps),
              "change": TerrainChange(remove=(last,)).to_dict(), "before": {last: {**data["holds"][i], "index": i}},
              "terrain_sha256_before": plan.terrain["sha256"]}
    ends_on_it = dataclasses.replace(plan, events=(forged,), terrain={
        **plan.terrain, "data": gone, "sha256": sha256_json({x: v for x, v in gone.items() if x != "description"})})
    found = [str(v) for v in verify(ends_on_it).violations]
    assert found == [f"plan: stance_change: unknown hold {last!r}"], found
    wrong_index = dataclasses.replace(new, steps=tuple(dataclasses.replace(s, index=0) for s in new.steps))
    assert any("steps[1].index = 0" in m for m in checks(wrong_index))


@pytest.mark.climb
@pytest.mark.parametrize("change, needle", [
    (TerrainChange(remove=("nope",)), "no hold 'nope'"),
    (TerrainChange(friction={"L3": -0.5}), "change.friction.L3"),
    (TerrainChange(move={"L3": (0.1, float("nan"))}), "change.move.L3"),
    (TerrainChange(), "empty"),
    (TerrainChange(add=({"id": "L3", "position": [0, 1], "normal": [0, 1]},)), "change.add"),
])
def test_bad_changes_are_refused(climb, change, needle):
    _, _, res = climb
    with pytest.raises(QueryError, match=needle):
        replan(res.plan, 1, change)


@pytest.mark.climb
def test_bad_step_and_bad_added_hold(climb):
    _, _, res = climb
    with pytest.raises(QueryError, match="at_step"):
        replan(res.plan, len(res.plan.steps), TerrainChange(remove=("L3",)))
    with pytest.raises(TerrainError, match="normal"):
        replan(res.plan, 1, TerrainChange(add=({"id": "new", "position": [0.1, 1.0], "normal": [0.0, 0.0],
                                                "friction": 0.9},)))
    # a loaded terrain keeps each hold's friction, not its file's default: a new hold must say its own (it got
    # 1.0, more than the 0.9 of a user's slab)
    with pytest.raises(QueryError, match="change.add: hold 'new' has no friction"):
        replan(res.plan, 1, TerrainChange(add=({"id": "new", "position": [0.1, 1.0], "normal": [0.0, 1.0]},)))


def _cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "climb_ompl", *args], capture_output=True, text=True, timeout=600)


@pytest.mark.climb
def test_a_rejoining_search_stops_at_its_stance_limit(monkeypatch):
    """A rejoining search stops at its stance limit, and the warm search to the goal finds the way, verified.  The
    limit is twice the climb's count, at least :data:`REJOIN_MIN_STANCES` (without it, a rejoin of the planar robot
    once explored about 300 nodes, 15 s of its quarter of the budget, against 22 for the whole climb).  Here the
    first failure of a longer planar climb (2.2 m) whose re-plan rejoins the old route after 4 or more nodes is
    re-planned again with the limit lowered to two."""
    import math

    from climb_ompl.climb import replan as rp

    robot, wall = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    stance, q0 = default_start(robot, wall, seed=0)
    res = plan_climb(robot, wall, stance, 2.2, q_start=q0, time_limit=60, seed=0)
    assert res.found, res.reason
    plan = res.plan
    lim = rp.rejoin_limit(plan)
    assert lim == max(rp.REJOIN_MIN_STANCES, math.ceil(rp.REJOIN_STANCES * plan.totals["stances_explored"]))

    def rejoins(out):
        return [s for s in out.stats.get("searches", []) if s["search"] == "rejoin"]

    grabs = [(k, plan.steps[i].hold) for k in range(1, len(plan.steps))
             for i in range(k, len(plan.steps)) if plan.steps[i].action == "grab"]
    at, hold = next((k, h) for k, h in grabs
                    if any(s["found"] and s["stances_explored"] >= 4
                           for s in rejoins(replan(plan, k, TerrainChange(remove=(h,)), robot=robot, rejoin=True))))
    monkeypatch.setattr(rp, "REJOIN_MIN_STANCES", 2)
    monkeypatch.setattr(rp, "REJOIN_STANCES", 0.0)
    assert rp.rejoin_limit(plan) == 2
    out = replan(plan, at, TerrainChange(remove=(hold,)), robot=robot, rejoin=True)  # from the plan alone
    rejoin = rejoins(out)
    assert rejoin and not rejoin[0]["found"] and rejoin[0]["stances_explored"] <= 3
    assert rejoin[0]["status"] == ClimbStatus.STANCE_LIMIT and out.stats["searches"][-1]["status"] == "found"
    assert out.found and verify(out.plan).ok


@pytest.mark.climb
def test_cli_replan_exit_codes(climb, tmp_path, cli):
    """A real subprocess for the re-plan that is found and the one that is not; the bad inputs (exit 2) in
    this process (the same ``main``, without a Python start-up each)."""
    _, _, res = climb
    plan_file = res.plan.save(tmp_path / "plan.json")
    hold = res.plan.steps[_next_grab(res.plan, 1)].hold
    out = tmp_path / "new.json"
    r = _cli("replan", str(plan_file), "--at-step", "1", "--remove-hold", hold, "--out", str(out))
    assert r.returncode == 0, r.stderr
    n_new = len(json.loads(out.read_text())["steps"]) - 1
    # a file as climb-ompl wrote it (steps_sha256) is not verified again; the table shows the whole new plan
    assert "steps valid" not in r.stderr and f"1 kept + {n_new} new" in r.stderr
    c = cli("replan", plan_file, "--at-step", "1", "--remove-hold", hold, "--check", "--out", tmp_path / "c.json")
    assert c.code == 0 and f"checked {plan_file}: {len(res.plan.steps)} steps valid" in c.err, c.err
    v = _cli("verify", str(out))
    assert v.returncode == 0, v.stderr
    assert json.loads(out.read_text())["events"][0]["change"]["remove"] == [hold]
    for args, needle in ((["--at-step", "99", "--remove-hold", hold], "--at-step: 99 steps executed"),
                         (["--at-step", "1", "--friction", f"{hold}=0.5", "--friction", f"{hold}=0.4"],
                          f"--friction {hold}: given twice"),
                         (["--at-step", "1", "--remove-hold", "nope"], "no hold 'nope'"),
                         (["--at-step", "1", "--friction", "nope=0.5"], "--friction: no hold 'nope'"),
                         (["--at-step", "1", "--move-hold", "nope=0,0,0"], "--move-hold: no hold 'nope'"),
                         (["--at-step", "1", "--friction", f"{hold}=abc"], "--friction"),
                         (["--at-step", "1", "--remove-hold", hold, "--set", "nosuch=2"], "--set nosuch: unknown"),
                         (["--at-step", "1", "--remove-hold", hold, "--set", "reexpand=-1"], "--set reexpand: -1"),
                         (["--at-step", "1", "--remove-hold", hold, "--time-limit", "0.01"], "--time-limit: 0.01 s is "
                          "too short"),  # it was raised to about a second without a word
                         (["--at-step", "1", "--add-holds", str(tmp_path / "none.yaml")], "--add-holds ")):
        bad = tmp_path / "bad.json"
        c = cli("replan", str(plan_file), *args, "--out", str(bad))
        assert c.code == 2 and needle in c.err and not bad.exists(), (args, c.err)
    # a plan edited by hand (a waypoint moved): its steps would be kept or copied, so it is refused
    d = json.loads(plan_file.read_text())
    longest = max(d["steps"], key=lambda st: len(st["waypoints"]))
    longest["waypoints"][len(longest["waypoints"]) // 2][0] += 0.3
    (tmp_path / "edited.json").write_text(json.dumps(d))
    c = cli("replan", str(tmp_path / "edited.json"), "--at-step", "1", "--remove-hold", hold, "--out",
            str(tmp_path / "e.json"))
    assert c.code == 2 and "the plan fails verify" in c.err and not (tmp_path / "e.json").exists()
    # every hold gone but the ones held: no way up, an answer with a reason (exit 1), no file
    held = set(dict(res.plan.steps[1].stance).values())
    gone = [h.id for h in Terrain.from_dict(res.plan.terrain["data"]).holds if h.id not in held]
    r = _cli("replan", str(plan_file), "--at-step", "1", *[x for h in gone for x in ("--remove-hold", h)],
             "--time-limit", "20", "--out", str(tmp_path / "none.json"))
    assert r.returncode == 1 and "no plan" in r.stderr and not (tmp_path / "none.json").exists(), r.stderr
    # a hold of the start stance removed: no state to resume from, said once (no back-off, no table of zeros)
    start_hold = sorted(set(dict(res.plan.start_stance).values()) & held)[0]  # still held after step 1
    older = tmp_path / "s.json"
    older.write_text("an older plan")  # left as it was, and said so
    c = cli("replan", plan_file, "--at-step", "1", "--remove-hold", start_hold, "--out", older)
    assert c.code == 1 and "(the start stance does)" in c.err and "backed off" not in c.err, c.err
    assert "one-step calls" not in c.err and older.read_text() == "an older plan"
    lib = replan(res.plan, 1, TerrainChange(remove=(start_hold,)))  # the same through the library: no search ran
    assert not lib.found and not lib.used and lib.climb.status == ClimbStatus.NO_START and not lib.stats
    assert f"note: nothing written; {older} is an older file, left as it was" in c.err


@pytest.mark.climb
def test_cli_replan_adds_holds_from_a_file(climb, tmp_path, cli):
    """``--add-holds FILE``: new holds in the terrain file's format, recorded in the event, the new plan verified;
    a new hold with a zero normal or an id in use, or a file that is no list of holds, is bad input naming the
    file (exit 2, no output file)."""
    import yaml

    _, wall, res = climb
    plan_file = res.plan.save(tmp_path / "plan.json")
    hold = res.plan.steps[_next_grab(res.plan, 1)].hold
    h = wall.hold(hold)
    new = [{"id": "bolt1", "position": [h.position[0] + 0.03, h.position[2] + 0.05], "normal": [0.0, 1.0],
            "friction": 0.9}]
    (tmp_path / "add.yaml").write_text(yaml.safe_dump({"friction": 0.9, "holds": [
        {k: v for k, v in new[0].items() if k != "friction"}]}))  # the file's default friction, as in a terrain
    c = cli("replan", plan_file, "--at-step", "1", "--remove-hold", hold, "--add-holds", tmp_path / "add.yaml",
            "--out", tmp_path / "new.json")
    assert c.code == 0, c.err
    event = json.loads((tmp_path / "new.json").read_text())["events"][0]
    assert event["change"]["add"][0]["id"] == "bolt1" and event["change"]["remove"] == [hold]
    assert event["change"]["add"][0]["friction"] == 0.9
    assert verify(tmp_path / "new.json").ok
    for holds, needle in (([{**new[0], "normal": [0.0, 0.0]}], "holds[0].normal: zero normal"),
                          ([{**new[0], "id": hold}], f"hold {hold!r} exists in terrain"),
                          ({"holds": 3}, "expected a list of holds"),
                          ({"holds": new, "gravity": [0.0, -9.81]}, "gravity: unknown field")):
        (tmp_path / "bad.yaml").write_text(yaml.safe_dump(holds))
        c = cli("replan", plan_file, "--at-step", "1", "--add-holds", tmp_path / "bad.yaml",
                "--out", tmp_path / "bad.json")
        assert c.code == 2 and f"--add-holds {tmp_path / 'bad.yaml'}:" in c.err and needle in c.err, c.err
        assert not (tmp_path / "bad.json").exists()


@pytest.mark.climb
def test_cli_replan_backs_off_from_a_removed_hold_underfoot(climb, tmp_path, cli):
    """Removing a hold a limb stands on after step 2 (and one the plan never uses): the new plan backs off to the
    last state that does not rely on it, and says so in steps executed, naming only the hold relied on; the kept
    steps are the old plan's."""
    _, _, res = climb
    plan = res.plan
    plan_file = plan.save(tmp_path / "plan.json")
    k = next(i for i in range(2, len(plan.steps)) if plan.steps[i - 1].action == "grab")
    held = plan.steps[k - 1].hold  # grabbed by step k (1-based), so the state after k steps stands on it
    used = {h for st in plan.steps for h in dict(st.stance).values()} | {st.hold for st in plan.steps}
    other = next(h.id for h in Terrain.from_dict(plan.terrain["data"]).holds if h.id not in used)
    c = cli("replan", plan_file, "--at-step", str(k), "--remove-hold", held, "--remove-hold", other, "--out",
            tmp_path / "new.json")
    assert c.code == 0, c.err
    back = json.loads((tmp_path / "new.json").read_text())["events"][0]["resumed_at_step"]
    assert back < k and f"backed off: kept {back} of the {k} steps executed" in c.err
    assert f"the state after {k} steps relies on a changed hold ({held})" in c.err
    assert "heights (m, along minus gravity): start holds" in c.err and "; end holds" in c.err  # as plan prints
    new = json.loads((tmp_path / "new.json").read_text())["steps"]
    assert [st["waypoints"] for st in new[:back]] == [st.to_dict()["waypoints"] for st in plan.steps[:back]]
    assert verify(tmp_path / "new.json").ok


@pytest.mark.climb
def test_playback_marks_the_failed_hold_and_the_departure(climb):
    """The playback of a re-planned climb draws the failed hold where it was before the change, and the
    departure; a plan without events draws neither."""
    import numpy as np

    from climb_ompl.viz import Scene, draw_climb, open_visualizer

    robot, wall, res = climb
    plan = res.plan
    hold = plan.steps[_next_grab(plan, 1)].hold
    out = replan(plan, 1, TerrainChange(remove=(hold,)), warm=res.search, robot=robot)
    assert out.found, out.climb.reason

    class Recording(Scene):
        def put(self, path, parts, **kw):
            self.drawn[path] = parts
            super().put(path, parts, **kw)

    for p, expect in ((plan, False), (out.plan, True)):
        with open_visualizer() as vis:
            scene = Recording(vis)
            scene.drawn = {}
            draw_climb(scene, p.to_dict(), robot=robot)
        events = {k: v for k, v in scene.drawn.items() if k.startswith("events/")}
        assert bool(events) == expect
    ball, label = events[f"events/e0/failed/{hold}"]
    assert np.allclose(ball.transform[:3, 3], wall.hold(hold).position)
    assert "events/e0/departure" in events
    # the hold is named beside it (a card textured with the rendered text, facing out of the wall)
    import io

    from PIL import Image

    from climb_ompl.model.wall_frame import wall_normal

    png = label.material.map.image.data
    alpha = np.asarray(Image.open(io.BytesIO(png)).convert("RGBA"))[:, :, 3]
    assert 0.02 < np.mean(alpha > 0) < 0.6  # text on a transparent background
    assert np.allclose(label.transform[:3, 2], wall_normal(wall))
    off = label.transform[:3, 3] - wall.hold(hold).position
    assert 0.05 < off @ -wall.g / np.linalg.norm(wall.g) and off @ wall_normal(wall) > 0.03


@pytest.mark.climb
def test_a_hold_held_before_it_failed_is_drawn_where_it_was(climb, tmp_path):
    """replan -> verify -> play for a hold the kept steps had held: playback draws each step on the terrain it was
    planned on, as verify checks it (before, play refused the plan: no such hold in the plan's terrain)."""
    from climb_ompl.viz import Scene, draw_climb, open_visualizer

    robot, wall, res = climb
    plan = res.plan
    # a hold of an early stance that the state after step k no longer relies on
    k, hold = next((k, h) for k in range(3, len(plan.steps)) for h in sorted(dict(plan.steps[1].stance).values())
                   if h not in dict(plan.steps[k].stance).values() and h != plan.steps[k - 1].hold
                   and all(h != st.hold for st in plan.steps[k:]))
    out = replan(plan, k, TerrainChange(remove=(hold,)), warm=res.search, robot=robot)
    assert out.found, out.climb.reason
    assert any(hold in dict(st.stance).values() for st in out.plan.steps[:k])  # the kept steps held it
    assert hold not in Terrain.from_dict(out.plan.terrain["data"]).hold_ids
    assert verify(out.plan).ok
    with open_visualizer() as vis:
        scene = Scene(vis)
        frames = draw_climb(scene, out.plan.to_dict(), robot=robot)
    assert {f.step for f in frames} >= set(range(len(out.plan.steps)))  # every step drawn


def test_playback_label_says_what_happened_to_the_hold():
    from climb_ompl.viz._plans import _what_changed

    change = {"remove": ["a"], "move": {"b": [0, 0, 1], "c": [0, 0, 1]}, "friction": {"c": 0.3}, "add": []}
    assert [_what_changed(change, h) for h in "abcd"] == ["removed", "moved", "moved and friction changed",
                                                          "changed"]
    assert _what_changed(None, "a") == "changed"


def _nudged(wall, hold):
    """The hold's position (x, z) on this 2-D wall, a millimetre along x."""
    x, _, z = wall.hold(hold).position
    return (float(x) + 0.001, float(z))


@pytest.mark.climb
def test_kept_route_is_the_old_route_unless_a_hold_of_it_is_gone(climb):
    from climb_ompl.climb.replan import kept_route, rejoin_index

    robot, wall, res = climb
    plan = res.plan
    k = 1
    hold = plan.steps[_next_grab(plan, k)].hold
    for change in (TerrainChange(move={hold: _nudged(wall, hold)}), TerrainChange(friction={hold: 0.5})):
        end = rejoin_index(plan, k, change.touched)
        assert end > _next_grab(plan, k)  # the route up to the rejoining step grabs the changed hold
        assert kept_route(plan, k, end, change) == tuple((s.action, s.limb, s.hold) for s in plan.steps[k:end])
    gone = TerrainChange(remove=(hold,))
    assert kept_route(plan, k, rejoin_index(plan, k, gone.touched), gone) is None


@pytest.mark.climb
def test_a_hold_moved_a_millimetre_keeps_the_old_route(climb):
    robot, wall, res = climb
    plan = res.plan
    k = 1
    hold = plan.steps[_next_grab(plan, k)].hold
    change = TerrainChange(move={hold: _nudged(wall, hold)})
    out = replan(plan, k, change, warm=res.search, robot=robot)
    assert out.found, out.climb.reason
    assert [(s.stance, s.action, s.limb, s.hold) for s in out.plan.steps] == \
        [(s.stance, s.action, s.limb, s.hold) for s in plan.steps]
    # the re-plan followed the old route (one stance per step up to the rejoining one), searching nothing else
    from climb_ompl.climb.replan import rejoin_index

    assert out.climb.stats["candidates"] == 1
    assert out.climb.stats["stances_explored"] == 1 + rejoin_index(plan, k, change.touched) - k
    rep = verify(out.plan)
    assert rep.ok, [str(v) for v in rep.violations[:5]]


@pytest.fixture(scope="module")
def lemur_climb():
    """LEMUR's 19-step climb to 1 m on the demo wall (seed 0)."""
    robot, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    stance, q0 = default_start(robot, wall, seed=0)
    res = plan_climb(robot, wall, stance, 1.0, q_start=q0, time_limit=60, seed=0)
    assert res.found, res.reason
    return robot, wall, res.plan


@pytest.mark.climb
@pytest.mark.parametrize("how", ["move", "friction"])
def test_lemur_keeps_its_route_when_a_hold_moves_2_cm_or_gets_slippery(lemur_climb, how):
    """LEMUR's route on the demo wall after a hold it grabs next moves 2 cm or loses 5 % of its friction: each
    step's transition is looked for about the old route's own transition first (its chains re-closed onto the
    moved hold), then about the configuration reached.  Drawn about the configuration reached only, the third
    step of the route (a grab with a margin of 9 mm) found no transition and the re-plan searched anew: 12 new
    steps instead of the route's 10 (the same for a hold that did not move at all)."""
    robot, wall, plan = lemur_climb
    k = 9
    hold = plan.steps[_next_grab(plan, k)].hold
    p = wall.hold(hold).position
    change = (TerrainChange(move={hold: (p[0] + 0.02, p[1], p[2])}) if how == "move"
              else TerrainChange(friction={hold: 0.95 * wall.hold(hold).friction}))
    out = replan(plan, k, change, robot=robot)
    assert out.found and out.resumed_at == k, out.climb.reason
    assert [(s.stance, s.action, s.limb, s.hold) for s in out.plan.steps] == \
        [(s.stance, s.action, s.limb, s.hold) for s in plan.steps]
    assert out.climb.stats["candidates"] == 1
    assert verify(out.plan).ok


@pytest.mark.climb
def test_a_second_failure_may_back_off_before_the_first_one(lemur_climb):
    """A second re-plan whose failed hold the robot has stood on since before the first re-plan backs off to
    before it: the new plan's events resume at step 9, then at an earlier step, and it verifies (``verify``
    took events out of order for a forged file)."""
    robot, wall, plan = lemur_climb
    first = replan(plan, 9, TerrainChange(remove=(plan.steps[_next_grab(plan, 9)].hold,)), robot=robot)
    assert first.found, first.climb.reason
    # the first step after the re-plan's own whose stance keeps a hold held without a break since step 1 (the
    # re-planned route, and so this step, may differ from run to run when a guard stops a FIND-PATH call)
    steps = first.plan.steps

    def kept(k: int) -> list[str]:
        held = [set(dict(steps[i].stance).values()) for i in range(2, k + 1)]  # (step 1 is a grab)
        return sorted(set.intersection(*held) & set(dict(plan.steps[1].stance_after).values()))

    k2 = next((k for k in range(12, len(steps)) if kept(k)), None)
    assert k2 is not None, "a hold held from step 1 to a step after the first re-plan's"
    old = kept(k2)
    second = replan(first.plan, k2, TerrainChange(remove=(old[0],)), robot=robot)
    assert second.found, second.climb.reason
    ks = [e["resumed_at_step"] for e in second.plan.events]
    assert ks[0] == 9 and ks[1] < 9 and second.backed_off
    rep = verify(second.plan)
    assert rep.ok, [str(v) for v in rep.violations[:5]]


@pytest.mark.climb
def test_bench_replan_fails_holds_as_asked():
    import numpy as np

    from climb_ompl.bench import replan as bench

    wall = Terrain.load("demo-wall")
    h = wall.holds[3]
    rng = np.random.default_rng(0)
    moved = bench.failure(wall, h.id, "move", rng).move[h.id]
    d = np.asarray(moved) - np.asarray(h.position)
    assert np.isclose(np.linalg.norm(d), bench.MOVE) and abs(d @ np.asarray(h.normal)) < 1e-12
    assert bench.failure(wall, h.id, "friction", rng).friction == {h.id: pytest.approx(bench.FRICTION * h.friction)}
    assert bench.failure(wall, h.id, "remove", rng).remove == (h.id,)
    planar = Terrain.load("planar-wall")
    x, _, z = planar.hold("L3").position
    (mx, mz), = bench.failure(planar, "L3", "move", rng).move.values()
    assert np.isclose(np.hypot(mx - x, mz - z), bench.MOVE)
    out = bench.run("planar-3limb", "planar-wall", height=0.6, failures=2, seed=0, time_limit=30, change="move")
    assert out["n"] >= 1 and out["found_warm"] >= out["found_scratch"] and out["verified_warm"] == out["found_warm"]
    assert all(r["change"]["move"] for r in out["runs"])
    # the steps that must be planned anew: at least the failed hold's grab, at most what is left
    assert all(1 <= r["relying"] <= r["remaining"] for r in out["runs"]) and 0 < out["median_relying_share"] <= 1
    with pytest.raises(ValueError, match="change"):
        bench.run("planar-3limb", "planar-wall", change="melt")


@pytest.mark.climb
def test_the_step_after_a_release_relies_on_the_released_hold(climb):
    """The motion after a release starts with that hand resting where the hold was (forward kinematics: within
    the hand-contact radius of it), so it relies on the hold: without it that hand starts in the wall. The old
    route is rejoined only after such a step, and a re-plan backs off before it."""
    import numpy as np

    from climb_ompl.climb.replan import rejoin_index, relies, state_relies
    from climb_ompl.contract import HAND_CONTACT_RADIUS

    robot, wall, res = climb
    plan = res.plan
    after = [i for i in range(1, len(plan.steps)) if plan.steps[i - 1].action == "release"]
    assert after
    for i in after:
        prev = plan.steps[i - 1]
        touched = frozenset({prev.hold})
        hand = robot.hand_position(np.asarray(plan.steps[i].waypoints[0]), prev.limb)
        target = robot.hand_target(prev.limb, wall.hold(prev.hold))
        assert np.linalg.norm(hand - target) <= HAND_CONTACT_RADIUS  # the oracle: the hand rests on the hold
        assert relies(plan, i, touched)
        assert rejoin_index(plan, max(0, i - 2), touched) > i
        # the state after the release (the hand resting where the hold was) relies on it: a re-plan from there
        # backs off before the release; one step later the hand has moved on
        assert state_relies(plan, i, touched) and resume_point(plan, i, touched) <= i - 1


@pytest.mark.climb
def test_a_rejoining_search_arrives_only_in_the_component_the_old_route_goes_on_from(climb):
    """A goal of stances with configurations to join (``WarmStart.joins``): a node of a listed stance meets the
    goal only with the elbow bends (the component label, Bretl 2006 sec. 4.2.3) of one of its configurations,
    here the signs of the contact limbs' elbow angles read off the configuration; other stances of the goal
    meet it in any component."""
    import numpy as np

    from climb_ompl.climb.goal import Goal
    from climb_ompl.climb.search import StanceGraphSearch
    from climb_ompl.climb.warm import WarmStart
    from climb_ompl.manifold.stance import Stance
    from climb_ompl.settings import ClimbSettings

    robot, wall, res = climb
    two = [s for s in res.plan.steps if len(s.stance) > 1]
    step, other = two[0], next(s for s in two if s.stance != two[0].stance)
    stance = Stance(dict(step.stance))
    q = np.asarray(step.waypoints[0], dtype=float)
    bends = tuple(int(np.sign(q[robot.limb(lb).elbow_index])) for lb in stance.limbs)  # the oracle
    assert all(bends)
    search = StanceGraphSearch(robot, wall, Goal("stances", stances=(step.stance, other.stance)), ClimbSettings())
    search.inherit(WarmStart(joins=((step.stance, q),)))
    assert search.arrived((stance, bends))
    flipped = tuple(-b if i == 0 else b for i, b in enumerate(bends))
    assert not search.arrived((stance, flipped))
    assert search.arrived((Stance(dict(other.stance)), flipped[:len(other.stance)]))  # not listed: any component
    third = Stance(dict(next(s.stance for s in res.plan.steps if s.stance not in (step.stance, other.stance))))
    assert not search.arrived((third, (1,) * len(third)))  # not a goal stance


@pytest.mark.climb
def test_a_warm_search_keeps_the_transitions_found_and_draws_the_failed_ones_again(climb):
    """The warm start keeps the first search's transitions found on stances that rely on no changed hold, and
    none of its failed FIND-TRANSITION calls (a failed call is a bounded number of draws, not a proof: a search
    from scratch draws again), nor its lowered edge probabilities."""
    import copy

    from climb_ompl.climb.edges import P_FAIL_FACTOR
    from climb_ompl.climb.goal import Goal
    from climb_ompl.climb.search import StanceGraphSearch
    from climb_ompl.climb.warm import WarmStart
    from climb_ompl.settings import ClimbSettings

    robot, wall, res = climb
    hold = res.plan.steps[_next_grab(res.plan, 1)].hold

    def clean(edge):
        return hold not in edge[0][0].hold_ids and hold not in edge[1].hold_ids

    old = copy.copy(res.search)  # the first search, with one of its clean edges failed instead
    old.transitions, old.edges = copy.copy(res.search.transitions), copy.copy(res.search.edges)
    old.transitions.by_edge, old.edges.prob = dict(res.search.transitions.by_edge), dict(res.search.edges.prob)
    lost = next(e for e, v in old.transitions.by_edge.items() if v is not None and clean(e))
    old.transitions.by_edge[lost], old.edges.prob[lost] = None, P_FAIL_FACTOR
    found = {e: v for e, v in old.transitions.by_edge.items() if v is not None}
    assert any(not clean(e) for e in found)  # some touch the removed hold
    search = StanceGraphSearch(robot, wall, Goal("height", height=1.6), ClimbSettings())
    search.inherit(WarmStart(search=old, touched=frozenset({hold})))
    assert set(search.transitions.by_edge) == {e for e in found if clean(e)}
    assert all(search.transitions.by_edge[e] is found[e] for e in search.transitions.by_edge)
    assert lost not in search.transitions.by_edge and not search.edges.prob and not search.edges.fails


@pytest.mark.climb
def test_a_replan_without_a_plan_carries_the_frontier_diagnosis(climb):
    """A gap: every hold between the ones held and those that meet the goal gone.  Wider than any two limbs span,
    it is answered at once, naming the gap.  0.7 m wide, the search runs and spends its budget: no plan, and the
    answering search's frontier comes with it (the CLI's hint reads it, as ``plan``'s does)."""
    _, _, res = climb
    terrain = Terrain.from_dict(res.plan.terrain["data"])
    kept = set(dict(res.plan.steps[1].stance).values()) | set(dict(res.plan.start_stance).values())
    top = max(terrain.height(h) for h in kept)
    goal = sorted(terrain.height(h.id) for h in terrain.holds)[-2]  # the goal's holds stay
    gone = tuple(h.id for h in terrain.holds if h.id not in kept and top < terrain.height(h.id) < goal)
    out = replan(res.plan, 1, TerrainChange(remove=gone), time_limit=4)
    assert not out.found and out.climb.status == ClimbStatus.GOAL_UNREACHABLE and not out.climb.diagnosis
    assert "a gap wider than the robot can span" in out.climb.reason
    gone = tuple(h.id for h in terrain.holds if h.id not in kept and top < terrain.height(h.id) < top + 0.7)
    out = replan(res.plan, 1, TerrainChange(remove=gone), time_limit=4)
    assert not out.found and out.used and out.climb.reason and "a gap wider" not in out.climb.reason
    assert out.climb.diagnosis and not any(set(d["stance"].values()) & set(gone) for d in out.climb.diagnosis)


@pytest.mark.climb
def test_every_held_hold_fails_in_turn_and_each_re_plan_plays(climb):
    """``bench replan --all-held`` on the planar climb: every hold the plan releases fails two steps after its first
    release, and each re-plan goes through replan, verify and play (the README's flow)."""
    from climb_ompl.bench.replan import every_held_hold

    robot, wall, res = climb
    out = every_held_hold(res.plan, robot, res.search)
    assert out["holds"] >= 2
    assert out["played"] == out["verified"] == out["found"] == out["holds"] and out["failures"] == [], out


@pytest.mark.climb
def test_after_a_removed_hold_the_new_steps_are_a_new_route_unless_rejoining_is_asked_for():
    """By default a removed hold's re-plan searches warm for the plan's goal, with no detour back onto the old route
    first; with ``rejoin=True`` it rejoins first; both verify.  (How long each way's new steps are against a plan
    from scratch from the same state is measured by ``climb-ompl bench replan``, over many failures.)  The planar
    robot's 2.2 m climb, its first grab's hold removed after step 1: the old route can be rejoined at step 6 of 13."""
    from climb_ompl.climb.replan import rejoin_index

    robot, wall = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    stance, q0 = default_start(robot, wall, seed=0)
    res = plan_climb(robot, wall, stance, 2.2, q_start=q0, time_limit=60, seed=0, keep_search=True)
    assert res.found, res.reason
    plan, k = res.plan, 1
    hold = plan.steps[_next_grab(plan, k)].hold
    change = TerrainChange(remove=(hold,))
    assert rejoin_index(plan, k, change.touched) < len(plan.steps)
    for rejoin, first in ((None, "goal"), (False, "goal"), (True, "rejoin")):
        out = replan(plan, k, change, warm=res.search, robot=robot, rejoin=rejoin)
        assert out.found and out.stats["searches"][0]["search"] == first, (rejoin, out.stats["searches"])
        assert verify(out.plan).ok
