"""The language server's client fixture: pytest-lsp starts ``irlc lsp`` and initializes a
session with the capabilities VS Code and Neovim announce (one server per test module and
client). Without pytest-lsp (the test extra) there is no fixture and the tests skip."""

from __future__ import annotations

try:
    import pytest_lsp
    from lsprotocol import types
    from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities
except ImportError:  # the test modules skip themselves (importorskip)
    pytest_lsp = None

if pytest_lsp is not None:
    from tests.lsp.lsp_client import COMMAND, UNITS, make_client

    @pytest_lsp.fixture(
        config=ClientServerConfig(server_command=COMMAND, client_factory=make_client),
        scope="module",
        params=["visual-studio-code", "neovim"],
    )
    async def client(lsp_client: LanguageClient, request):
        capabilities = client_capabilities(request.param)
        result = await lsp_client.initialize_session(
            types.InitializeParams(capabilities=capabilities)
        )
        lsp_client.server_capabilities = result.capabilities
        UNITS["encoding"] = result.capabilities.position_encoding or "utf-16"  # as negotiated
        yield
        await lsp_client.shutdown_session()
