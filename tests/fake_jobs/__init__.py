"""Fake studies for ``adcskit reproduce --jobs`` (tests/test_jobs.py): each module defines ``STUDY``.

``b``: the fake study (tests/fake_study.py) under another name; ``boom``: raises;
``sleepy``: sleeps until interrupted (at most 20 s); ``interrupter``: waits until the fake
study's log under ``$ADCSKIT_TEST_OUT`` says it is done, then sends SIGINT to the parent
process (a Ctrl-C) and sleeps until interrupted.
"""
