from dataclasses import replace

import fake_study


def run(config, **kw):
    return replace(fake_study.run(config, **kw), study="fake-b")


STUDY = replace(fake_study.STUDY, name="fake-b", run=run)
