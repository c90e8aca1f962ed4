"""Fixtures of the fuzzers: one reader process for the session, and the tally at the end."""

import pytest

from .harness import TALLY, Worker


@pytest.fixture(scope="session")
def worker():
    w = Worker()
    yield w
    w.close()


def pytest_terminal_summary(terminalreporter):
    if not TALLY:
        return
    terminalreporter.section("fuzzed inputs per reader")
    for name, counts in sorted(TALLY.items()):
        total = sum(counts.values())
        parts = ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
        terminalreporter.write_line(f"{name}: {total} inputs ({parts})")
