"""A learned motion as data: the network (``network``), the model around it with its inputs,
outputs and metadata (``motion_model.MotionModel``), its file (``model_file``: ``.mimic``) and
the foot track a cyclic model carries (``foot_track``).

``learn`` writes these; the agents that play them (``agents.neural_player``) read them. This
layer sits below both, so playing a model never imports the code that trains one.
"""
