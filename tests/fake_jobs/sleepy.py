import time
from dataclasses import replace

import fake_study


def run(config, **kw):
    time.sleep(20.0)  # interrupted by the parent's SIGINT long before
    return replace(fake_study.run(config, **kw), study="fake-sleepy")


STUDY = replace(fake_study.STUDY, name="fake-sleepy", run=run)
