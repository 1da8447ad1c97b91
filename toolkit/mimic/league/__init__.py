"""The RoboCup Soccer 3D league's server, RCSSServerMJ (``rcsssmj``): its wire and its files.

* ``server``: host the server (a subprocess on free ports, headless, lock-step by default);
  ``hosted_server``: what that subprocess runs (``python -m rcsssmj`` with safe sends).
* ``protocol``: length-prefixed s-expression messages; ``names``: a robot's wire names.
* ``client``: one player (perceptions in, PD motor commands out); ``monitor``: the scene
  stream and referee commands; ``rsmp``: full and diff frames of the scene graph.
* ``decode``: joint angles and link poses from the scene graph through the robot's tree.
* ``senses``: a player's perceptions read straight from the simulation's MjData.
* ``field``: the installed server's soccer world file, its step and air.
* ``untrusted``: limits and printing for what another process sends; ``errors``.

The league's worlds are beside ours in ``world/`` (``league_server``: a player on a hosted
server; ``league_inprocess``: its simulation stepped in this process); recording another
team's player from the monitor or a game log is in ``recording/`` (``blackbox``,
``game_log``); a mimic agent as a team process in ``team/``.

Everything is imported on first use (``from mimic.league.client import AgentClient``).
"""

__all__ = [
    "server",
    "hosted_server",
    "protocol",
    "names",
    "client",
    "monitor",
    "rsmp",
    "decode",
    "senses",
    "field",
    "untrusted",
    "errors",
]
