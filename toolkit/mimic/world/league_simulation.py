"""rcsssmj's soccer simulation as ``LeagueInProcessWorld`` steps it in mimic's process.

``LeagueSimulation`` is rcsssmj's ``SoccerSimulation`` (the server's world MJCF, solver options,
robot models, rule book, field and referee) with three changes that alter no result, only
time and trouble: no audio step (nobody speaks; the audio engine changes only what a
microphone hears), the ball's touches (which the referee judges) found through a table made
once per model instead of a name lookup per contact each cycle, and a joining robot's controls
zeroed before the first forward pass (a server leaves them uninitialised until the agent's
first command, and MuJoCo warns about them into ``MUJOCO_LOG.TXT`` in the working directory).
"""

from __future__ import annotations

import mujoco
from rcsssmj.games.soccer.game_phase import GamePhase
from rcsssmj.games.soccer.sim.soccer_ball import SoccerBall
from rcsssmj.games.soccer.sim.soccer_referee import SoccerReferee
from rcsssmj.games.soccer.sim.soccer_sim import SoccerSimulation
from rcsssmj.games.soccer.soccer_fields import create_soccer_field
from rcsssmj.games.soccer.soccer_rules import SoccerRuleBooks, create_soccer_rule_book
from rcsssmj.sim.agent_id import decode_agent_prefix
from rcsssmj.sim.audio_engine import a_forward, a_recompile

__all__ = ["LeagueSimulation"]


class _Ball(SoccerBall):
    """rcsssmj's ball; who touches it (for the referee) found through a table of the geoms'
    owners made once per model, not a name lookup per contact each cycle. The same result
    as ``SoccerBall.post_step`` (``filter_agent_contacts_with``), in the same order."""

    def bind(self, mj_model, mj_data) -> None:
        super().bind(mj_model, mj_data)
        self._geom = mujoco.mj_name2id(mj_model, mujoco.mjtObj.mjOBJ_GEOM, "ball")
        names = [
            mujoco.mj_id2name(mj_model, mujoco.mjtObj.mjOBJ_GEOM, g) for g in range(mj_model.ngeom)
        ]
        self._owner = [(decode_agent_prefix(n) if n else None, n) for n in names]

    def post_step(self, mj_model, mj_data) -> None:
        pairs = mj_data.contact.geom.tolist()  # (ncon, 2) geom ids
        ball = self._geom
        others = [a for a, b in pairs if b == ball] + [b for a, b in pairs if a == ball]
        contacts: dict = {}
        for g in others:
            agent, name = self._owner[g]
            if agent is not None:
                contacts.setdefault(agent, set()).add(name)
        # SoccerBall.post_step from here on
        if contacts:
            if self._active_contact not in contacts:
                active = next(iter(contacts))
                self._set_active_contact(active, contacts[active], mj_data.time)
            else:
                self._active_contact_body_parts = contacts[self._active_contact]
        else:
            self._set_active_contact(None, None, mj_data.time)


class LeagueSimulation(SoccerSimulation):
    """rcsssmj's soccer simulation with changes that alter no result: a step skips the audio
    engine once ``hearing`` is off (nobody speaks in mimic's worlds); a recompiled model's
    controls start at zero (``MjSpec.recompile`` leaves a joining robot's uninitialised, and
    MuJoCo then warns about them into ``MUJOCO_LOG.TXT`` in the working directory); the ball
    is ``_Ball``. Built with the server's default rule book and field."""

    #: Run the audio engine in a step (it must, before a player joins: rcsssmj 0.2.1's fails on
    #: a player joining before the first cycle).
    hearing = True

    def __init__(self) -> None:
        # The server's defaults: ``rcssservermj`` without ``--rules``, ``--field``, ``--phase``.
        book = create_soccer_rule_book(SoccerRuleBooks.SSIM.value)
        super().__init__(
            field=create_soccer_field(book.default_field_version.value),
            rules=book,
            referee=SoccerReferee(),
            initial_game_phase=GamePhase.FIRST_HALF,
        )
        self.ball = _Ball()

    def step(self, monitor_commands) -> None:
        if self.hearing:
            super().step(monitor_commands)
            return
        # BaseSimulation.step without a_step: pre-step, physics, post-step (monitor commands,
        # referee), frame count.
        self._pre_step()
        mujoco.mj_step(self._mj_model, self._mj_data, self.n_substeps)
        self._post_step(monitor_commands)
        self._frame_id += 1

    def _recompile(self) -> None:
        # BaseSimulation._recompile, the controls zeroed before the first forward pass.
        self._last_recompilation = self._frame_id
        self._mj_model, self._mj_data = self._mj_spec.recompile(self._mj_model, self._mj_data)
        self._mj_data.ctrl[:] = 0.0
        mujoco.mj_forward(self._mj_model, self._mj_data)
        self._a_data = a_recompile(self._mj_spec, self._a_data)
        a_forward(self._a_data, self._mj_data)
        for obj in self.sim_objects:
            obj.bind(self._mj_model, self._mj_data)
        self._update_body_children_map()
