"""Keyframe motions: steps, movements, C2 cubic-spline interpolation, our motion files."""
