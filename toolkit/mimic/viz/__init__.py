"""How things look in Rerun: recordings, comparisons, training curves, trial dashboards.

Every function takes an explicit ``rr.RecordingStream``; nothing logs to a global stream.
"""
