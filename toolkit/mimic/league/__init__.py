"""The RoboCup Soccer 3D league's server, RCSSServerMJ (``rcsssmj``), as a mimic world.

* ``server``: host the server (a subprocess on free ports, headless, lock-step by default).
* ``protocol``: length-prefixed s-expression messages; ``names``: a robot's wire names.
* ``client``: one player (perceptions in, PD motor commands out); ``monitor``: the scene
  stream and referee commands; ``rsmp``: full and diff frames of the scene graph.
* ``decode``: joint angles and link poses from the scene graph through the robot's tree.
* ``world``: ``LeagueWorld``, the world interface on a server (episodes run unchanged).
* ``inprocess``: ``LeagueInProcessWorld``, the same world with the server's own simulation
  stepped in this process (``simulation``: rcsssmj's, ``senses``: its perceptions from MjData).
* ``play``: any agent as a team process; ``blackbox``: record another team's player from
  the monitor stream; ``game_log``: the same from ``--logfile`` game logs.

Everything is imported on first use (``from mimic.league.world import LeagueWorld``).
"""

__all__ = [
    "server",
    "protocol",
    "names",
    "client",
    "monitor",
    "rsmp",
    "decode",
    "world",
    "inprocess",
    "simulation",
    "senses",
    "play",
    "blackbox",
    "game_log",
    "player_writer",
    "errors",
    "sigint",
]
