"""One episode layer: a scene set up from a random generator, one control loop, observers.

Recording, trials, motion checks and the other team's checks are all
``Scene.setup(world, rng)`` + ``run(world, agent, ...)`` (or ``Episode.run``) + observers.
"""

from mimic.episode.episode import Episode
from mimic.episode.observers import EpisodeTrace, FallCounter, Observer, PoseTrace, UprightLog
from mimic.episode.run import RunOutcome, run
from mimic.episode.scene import Placement, PoseNoise, Scene

__all__ = [
    "Scene",
    "PoseNoise",
    "Placement",
    "run",
    "RunOutcome",
    "Episode",
    "Observer",
    "FallCounter",
    "UprightLog",
    "PoseTrace",
    "EpisodeTrace",
]
