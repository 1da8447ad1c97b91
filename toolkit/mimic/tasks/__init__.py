"""Tasks: a scenario as one object (its config, scene, episode, rows, summary, score, columns)."""
