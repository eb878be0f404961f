"""``irlc lsp`` as a command: without the optional extra it says which one to install."""

from __future__ import annotations

import sys

from irlc.cli import main


def test_without_the_extra_it_names_the_extra(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "pygls.lsp.server", None)  # as if pygls were missing
    assert main(["lsp"]) == 3
    err = capsys.readouterr().err
    assert err.startswith("irlc: error: lsp: the language server needs the extra lsp")
    assert "pip install 'irlc[lsp]'" in err and "Traceback" not in err


def test_its_help_says_what_it_does(capsys):
    assert main(["lsp", "--help"]) == 0
    out = capsys.readouterr().out
    assert "Language server" in out and "irlc[lsp]" in out
