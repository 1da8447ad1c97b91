"""``mimic improve``: CMA-ES on a keyframe motion, a learned model or an engine's parameters,
scored by the trials' episodes, validated on episodes the search never played.

``improve()`` is the whole run as one function (the CLI is a thin shell around it):

    from mimic.improve import improve
    run = improve("kick_right", objective="kick", budget=40, out=Path("kick_better.txt"))
    run.validation.summary

Modules: ``space`` (parameters in search units), ``targets`` (what can change, back to agents
and files), ``correction`` (the learned-model correction), ``objectives`` (scores from trial
episodes), ``search`` (CMA-ES, checkpoints), ``validation`` (held-out episodes), ``run``.
"""

from mimic.improve.run import ImproveRun, improve

__all__ = ["improve", "ImproveRun"]
