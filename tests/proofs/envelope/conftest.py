"""The sweep the killed-worker tests of local workers and of Ray compare with, made once."""

import pytest

from atcs.proofs.envelope import sweep
from atcs.proofs.envelope.executors import local_executor


@pytest.fixture(scope="session")
def undisturbed_sweep():
    """Three of the envelope's curve properties (``test_ray._names``) swept by one local worker, no worker killed:
    the map a sweep with a worker killed must give, verdict for verdict."""
    from tests.proofs.envelope.test_ray import CONFIG, _names

    with local_executor(1) as tasks:
        return sweep(CONFIG, _names(), timeout_s=300, executor=tasks)
