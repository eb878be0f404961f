"""``irlc lsp``: a Language Server Protocol server for IRL programs and their data lists.

Editors (VS Code with ``editors/vscode``, Neovim, Emacs, …) start it and speak LSP with it
over the standard input and output. It shows the compiler's own diagnostics as the text is
typed, and answers completion, hover, go to definition and document symbols. Its parts:

- :mod:`.analysis`: a program compiled by the compiler's pipeline, indexed on demand.
- :mod:`.index`: what each name written in the program stands for.
- :mod:`.diagnostics`, :mod:`.completion`, :mod:`.hover`, :mod:`.navigation`: the features.
- :mod:`.positions`: the compiler's spans ↔ LSP positions.
- :mod:`.server`: the pygls server that ties them to the protocol.

It needs the optional extra ``lsp`` (pygls, lsprotocol): ``pip install 'irlc[lsp]'``.
"""

from __future__ import annotations

EXTRA_HINT = "pip install 'irlc[lsp]'"


def missing_dependency() -> str | None:
    """What is missing for the server (``None``: pygls and lsprotocol import)."""
    try:
        import lsprotocol.types  # noqa: F401
        import pygls.lsp.server  # noqa: F401
    except ImportError as e:
        return f"{e.name or 'pygls'} is not installed"
    return None
