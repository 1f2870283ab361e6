import os
import signal
import time
from dataclasses import replace
from pathlib import Path

import fake_study


def run(config, **kw):
    # the fake study's log gets its "done" line once that worker is past the study
    log = Path(os.environ["ADCSKIT_TEST_OUT"]) / "logs" / "fake.log"
    for _ in range(1200):  # at most 60 s (a slow, loaded CI machine)
        if log.is_file() and "fake: done in" in log.read_text():
            break
        time.sleep(0.05)
    os.kill(os.getppid(), signal.SIGINT)  # Ctrl-C in the parent (the adcskit process)
    time.sleep(20.0)  # interrupted by the parent's SIGINT long before
    return replace(fake_study.run(config, **kw), study="fake-int")


STUDY = replace(fake_study.STUDY, name="fake-int", run=run)
