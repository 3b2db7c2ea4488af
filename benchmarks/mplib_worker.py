"""mplib's side of benchmarks/planning.py, run in mplib's own venv (mplib 0.2.1 needs numpy < 2): reads a job
(the URDF, the cell as plain shapes, the start, the targets) as JSON on stdin, plans each target with
mplib's RRT-Connect and prints, per plan, the wall time, whether it succeeded and the joint path, as JSON.

Only numpy and mplib here: the pendant's package is not importable in that venv.
"""

from __future__ import annotations

import json
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from mplib import Planner, Pose
from mplib.collision_detection import fcl


def _shape(obstacle: dict) -> object:
    kind = obstacle["kind"]
    if kind == "box":
        return fcl.Box(np.array(obstacle["sides"]))
    if kind == "capsule":
        return fcl.Capsule(obstacle["radius"], obstacle["length"])
    if kind == "sphere":
        return fcl.Sphere(obstacle["radius"])
    return fcl.Halfspace(np.array(obstacle["normal"]), obstacle["offset"])


def main() -> None:
    job = json.load(sys.stdin)
    with tempfile.TemporaryDirectory() as folder:
        # mplib writes its generated SRDF next to the URDF: give it a copy.
        urdf = Path(folder) / Path(job["urdf"]).name
        shutil.copy(job["urdf"], urdf)
        planner = Planner(str(urdf), move_group=job["move_group"])
        for obstacle in job["obstacles"]:
            shape = fcl.CollisionObject(_shape(obstacle), Pose(np.array(obstacle["T"])))
            planner.planning_world.add_object(obstacle["name"], shape)
        # As in the pendant's check: the base stands on the floor, and is not checked against obstacles.
        allowed = planner.planning_world.get_allowed_collision_matrix()
        for obstacle in job["obstacles"]:
            allowed.set_entry(job["base_link"], obstacle["name"], True)
        for k, capsule in enumerate(job["tool"]):
            planner.update_attached_object(
                _shape(capsule), Pose(np.array(capsule["T"])), name=f"tool{k}", link_id=job["tool_link"]
            )
        fingers = np.zeros(len(planner.joint_limits) - len(job["start"]))  # the gripper's, closed
        start = np.concatenate([job["start"], fingers])
        results = []
        for target in job["targets"]:
            began = time.perf_counter()
            goal = np.concatenate([target, fingers])
            answer = planner.plan_qpos([goal], start, planning_time=job["budget_s"])
            seconds = time.perf_counter() - began
            ok = answer.get("status") == "Success"
            path = np.asarray(answer["position"])[:, : len(target)].tolist() if ok else []
            results.append({"seconds": seconds, "success": ok, "path": path})
    print(json.dumps(results))


if __name__ == "__main__":
    main()
