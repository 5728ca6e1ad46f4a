"""Settings of the command-line tests."""

import pytest


@pytest.fixture(autouse=True)
def _consoles_as_wide_as_a_wide_terminal(monkeypatch):
    """The commands' consoles 200 columns wide, whatever terminal runs the tests.

    rich reads ``COLUMNS`` once, when a console is made (at import), so a
    test's ``env={"COLUMNS": ...}`` cannot widen it: under ``COLUMNS=80`` a
    table's cells wrapped and a test reading a row failed.
    """
    from collisionkit.cli import _messages

    for console in (_messages.console, _messages.error_console):
        monkeypatch.setattr(console, "width", 200)
