"""Seeded physical outcome checks shared by the tests and the benchmarks.

``motions``: our keyframe motions (a kick from a stand, a get-up, standing still).
``walking``: any walk or kick agent through its interface only (a straight walk, a kick from
a stand), as the recorder sees the other team. Kicks from a stand, get-ups, standing and
straight walks are tasks of ``mimic.tasks`` played with each check's config.
"""
