"""What the tests share."""

import signal

import pytest


@pytest.fixture
def interruptible():
    """Ctrl-C (SIGINT) raises KeyboardInterrupt during the test, as in an
    interactive interpreter, even where the process was started with SIGINT
    ignored (a background job of a shell): Python then installs no handler
    of its own, and the tests' SIGINT would go unnoticed."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)
