"""Team processes: a mimic agent as an ordinary player on a league server.

* ``play``: any agent in the league world on a server (``world.league_server``), recorded
  as it plays; ``mimic play`` calls it.
* ``other_team_t1``: the T1 other team (``agents.other_team_t1``) as a team process
  (``python -m mimic.team.other_team_t1 --server HOST:PORT``).
"""

__all__ = ["play", "other_team_t1"]
