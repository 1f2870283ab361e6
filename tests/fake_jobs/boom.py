from dataclasses import replace

import fake_study


def run(config, **kw):
    raise RuntimeError("boom: fake study failed on purpose")


STUDY = replace(fake_study.STUDY, name="fake-boom", run=run)
