"""rcsssmj's soccer simulation as ``LeagueInProcessWorld`` steps it in mimic's process.

``LeagueSimulation`` is rcsssmj's ``SoccerSimulation`` (the server's world MJCF, solver options,
robot models, rule book, field and referee) with changes that alter no result, only time and
trouble: no audio step (nobody speaks; the audio engine changes only what a microphone hears);
the ball's touches (which the referee judges) found through a table made once per model
instead of a name lookup per contact each cycle; two of the referee's per-cycle checks skipped
where they cannot act (``_Referee``); the simulation objects' hooks called from a list made
once per model instead of a chain built twice a cycle; and a joining robot's controls zeroed
before the first forward pass (a server leaves them uninitialised until the agent's first
command, and MuJoCo warns about them into ``MUJOCO_LOG.TXT`` in the working directory).

The referee's and the ball's overrides restate rcsssmj 0.2.1's code (``pyproject.toml`` pins
that version); ``tests/test_league_inprocess.py`` checks perceptions against a hosted server
bit for bit, so a version whose rules differ fails there.
"""

from __future__ import annotations

import mujoco
from rcsssmj.games.soccer.game_phase import GamePhase
from rcsssmj.games.soccer.play_mode import PlayMode
from rcsssmj.games.soccer.sim import soccer_referee
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


#: The play modes with a timeout in rcsssmj 0.2.1's ``SoccerReferee._check_timeouts`` (set
#: plays, goal kicks, the pause after a goal): in any other its checks are all false.
_TIMED_PLAY_MODES = frozenset(
    PlayMode[name]
    for side in ("LEFT", "RIGHT")
    for name in (
        f"KICK_OFF_{side}",
        f"THROW_IN_{side}",
        f"CORNER_KICK_{side}",
        f"FREE_KICK_{side}",
        f"DIRECT_FREE_KICK_{side}",
        f"GOAL_KICK_{side}",
        f"GOAL_{side}",
    )
)

#: The play modes with placement rules in rcsssmj 0.2.1's
#: ``SoccerReferee._penalize_misplaced_players`` (set plays): in any other it checks nothing.
_PLACED_PLAY_MODES = _TIMED_PLAY_MODES - {PlayMode.GOAL_LEFT, PlayMode.GOAL_RIGHT}

#: The play modes in which rcsssmj 0.2.1's ``SoccerReferee._check_contact_triggers`` acts on a
#: touch of the ball (the set plays but goal kicks): in any other it does nothing.
_TOUCHED_PLAY_MODES = _PLACED_PLAY_MODES - {PlayMode.GOAL_KICK_LEFT, PlayMode.GOAL_KICK_RIGHT}

#: The play modes in which rcsssmj 0.2.1's ``SoccerReferee._check_location_triggers`` acts on
#: more than a ball in a goal or off the field: the goal kicks (a ball out of the goalie area).
_GOAL_KICKS = frozenset({PlayMode.GOAL_KICK_LEFT, PlayMode.GOAL_KICK_RIGHT})


class _Referee(SoccerReferee):
    """rcsssmj's referee; five per-cycle checks skipped where they cannot act:

    * the timeouts in a play mode that has none (``BeforeKickOff``, in which mimic's worlds
      play, ``PlayOn``, offside, game over): every test in ``_check_timeouts`` is false there;
    * the illegal defence when neither team has more players than may stand in its goalie
      area: no area can then hold too many, so nobody can be penalised. The check's entry
      times are read only for a penalty; a team that grows past the limit is checked in
      full from then on (mimic's in-process world has one player, so none does);
    * the players' placement in a play mode without placement rules (all but set plays);
    * the location triggers while the ball lies on the field and in neither goal, outside
      goal kicks: each of their tests is then false (read once, as floats, the same values);
    * the contact triggers outside the set plays they end (``PlayOn`` among them).
    """

    def _check_contact_triggers(self) -> None:
        if self.game.game_state.play_mode in _TOUCHED_PLAY_MODES:
            super()._check_contact_triggers()

    def _check_location_triggers(self) -> None:
        if not self._did_act and self.game.game_state.play_mode not in _GOAL_KICKS:
            x, y, z = self.game.ball.xpos.tolist()
            field = self.game.field
            if (
                field.field_area.contains(x, y)
                and not field.left_goal_box.contains(x, y, z)
                and not field.right_goal_box.contains(x, y, z)
            ):
                return
        super()._check_location_triggers()

    def _check_timeouts(self) -> None:
        if self.game.game_state.play_mode in _TIMED_PLAY_MODES:
            super()._check_timeouts()

    def _check_illegal_defense(self) -> None:
        most = soccer_referee._ILLEGAL_DEFENSE_MAX_PLAYERS
        if len(self.game.left_players) > most or len(self.game.right_players) > most:
            super()._check_illegal_defense()
            return
        violations = self._illegal_defense_violation_steps
        violations["left"] = violations["right"] = 0

    def _penalize_misplaced_players(self) -> None:
        if self.game.game_state.play_mode in _PLACED_PLAY_MODES:
            super()._penalize_misplaced_players()


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
            referee=_Referee(),
            initial_game_phase=GamePhase.FIRST_HALF,
        )
        self.ball = _Ball()

    def step(self, monitor_commands) -> None:
        if self.hearing:
            super().step(monitor_commands)
            return
        # BaseSimulation.step without a_step: pre-step, physics, post-step (the objects'
        # hooks, monitor commands, referee), frame count; the objects as ``sim_objects``
        # lists them (ball, left players, right players), from the list made at binding.
        m, d, objects = self._mj_model, self._mj_data, self._objects
        for obj in objects:
            obj.pre_step(m, d)
        mujoco.mj_step(m, d, self.n_substeps)
        for obj in objects:
            obj.post_step(m, d)
        for command in monitor_commands:
            command.perform(self)
        self.referee.referee()
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
        self._objects = tuple(self.sim_objects)
