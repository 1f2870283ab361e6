from dataclasses import replace

import adcskit._progress as progress
import fake_study


def run(config, **kw):
    progress.status("fake-stages: stage one")
    progress.status("stage two (no name)")  # the worker names it
    every, progress.FORWARD_EVERY_S = progress.FORWARD_EVERY_S, 0.0  # a line after every item below
    try:
        for _ in progress.track(range(3), "fake loop"):
            pass
    finally:
        progress.FORWARD_EVERY_S = every
    return replace(fake_study.run(config, **kw), study="fake-stages")


STUDY = replace(fake_study.STUDY, name="fake-stages", run=run)
