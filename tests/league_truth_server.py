"""RCSSServerMJ with a ground-truth monitor: ``python league_truth_server.py TRUTH.jsonl ARGS``.

Runs the league server exactly as ``python -m rcsssmj ARGS`` does, with one more monitor inside
the server process: at every frame the monitors see (every second cycle) it writes the true
MuJoCo state of every robot as one JSON line: server time, each hinge's ``qpos`` and the pose
its bodies are drawn at, and the torso pose. The bodies' poses (``xpos``) that frames carry are
computed before the last physics step's integration, so the pose a frame shows is the joint
state one step earlier, ``qpos - timestep * qvel`` (Euler and implicit integrators both
advance positions with the new velocity): ``shown`` holds that true state one step before the
frame's time, ``qpos`` the state at the frame's time. Tests compare what mimic decodes with
both. ``ball`` is the ball's free joint ``qpos`` at the frame's time (position, quaternion).
"""

from __future__ import annotations

import json
import sys

from rcsssmj import __main__ as server_main
from rcsssmj.games.soccer.server.soccer_server import SoccerSimServer
from rcsssmj.server.remote_monitor import SimMonitor
from rcsssmj.sim.state_info import SceneGraph

from mimic.league import hosted_server


class TruthMonitor(SimMonitor):
    """Writes the true state of every robot at every monitor frame."""

    def __init__(self, path: str) -> None:
        super().__init__(update_interval=2)
        self._file = open(path, "w", buffering=1)

    def update(self, state_info, frame_id: int, last_recompilation: int) -> None:
        if frame_id % self.update_interval != 0:
            return
        graph = next((s for s in state_info if isinstance(s, SceneGraph)), None)
        if graph is None:
            return
        m, d = graph.mj_model, graph.mj_data
        dt = float(m.opt.timestep)
        players = {}
        for agent in graph.sim_agents:
            prefix = agent.agent_id.prefix
            qpos, shown = {}, {}
            for j in range(m.njnt):
                name = m.joint(j).name
                if name.startswith(prefix) and m.jnt_type[j] == 3:  # hinge
                    q, v = float(d.qpos[m.jnt_qposadr[j]]), float(d.qvel[m.jnt_dofadr[j]])
                    qpos[name[len(prefix) :]] = q
                    shown[name[len(prefix) :]] = q - dt * v
            torso = m.body(agent.root_body_name).id
            players[f"{agent.team_name} {agent.agent_id.player_no}"] = {
                "qpos": qpos,
                "shown": shown,
                "torso": [*map(float, d.xpos[torso]), *map(float, d.xquat[torso])],
            }
        ball = m.joint("ball-root")
        ball_qpos = d.qpos[ball.qposadr[0] : ball.qposadr[0] + 7]
        entry = {"t": float(d.time), "players": players, "ball": [*map(float, ball_qpos)]}
        self._file.write(json.dumps(entry) + "\n")

    def shutdown(self) -> None:
        super().shutdown()
        self._file.close()


def main() -> None:
    truth_path = sys.argv.pop(1)
    plain_init = SoccerSimServer.__init__

    def init(self, *args, **kwargs) -> None:
        plain_init(self, *args, **kwargs)
        self._monitors.append(TruthMonitor(truth_path))

    SoccerSimServer.__init__ = init
    hosted_server.apply()  # as mimic hosts it: sends safe against a peer that leaves
    server_main.soccer_sim()


if __name__ == "__main__":
    main()
