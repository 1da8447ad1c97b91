"""The study's statistical trials: kick (walk to the ball, kick, repeat) and walk (15 m)."""
