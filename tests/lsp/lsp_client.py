"""The LSP test client's helpers: positions in a text in the negotiated encoding, opening
and changing documents, waiting for their diagnostics, and the requests the tests make."""

from __future__ import annotations

import asyncio
import shutil
import sys
from pathlib import Path

from lsprotocol import types
from pygls.protocol import default_converter
from pygls.uris import from_fs_path
from pytest_lsp import LanguageClient
from pytest_lsp.client import DEFAULT_CLIENT_FEATURES, register_lsp_features

ROOT = Path(__file__).resolve().parents[2]
IRLC = shutil.which("irlc", path=str(Path(sys.executable).parent))
COMMAND = [IRLC, "lsp"] if IRLC else [sys.executable, "-c", "from irlc.cli import entry; entry()",
                                       "lsp"]  # fmt: skip
TIMEOUT = 30.0  # s: a loaded 2-core machine, the server's first compile
UNITS = {"encoding": "utf-16"}  # the position encoding of the client the fixture started


def make_client() -> LanguageClient:
    """pytest-lsp's test client, also recording the version of each diagnostics message."""
    client = LanguageClient(converter_factory=default_converter)
    client.diagnostic_versions = {}

    def published(client: LanguageClient, params: types.PublishDiagnosticsParams) -> None:
        client.diagnostics[params.uri] = params.diagnostics
        client.diagnostic_versions[params.uri] = params.version

    features = {**DEFAULT_CLIENT_FEATURES, types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS: published}
    register_lsp_features(client, features)
    return client


def uri(path: Path) -> str:
    return from_fs_path(str(path))


def units(text: str) -> int:
    """The length of ``text`` in the code units of the negotiated position encoding."""
    encoding = {"utf-8": "utf-8", "utf-16": "utf-16-le", "utf-32": "utf-32-le"}
    size = {"utf-8": 1, "utf-16": 2, "utf-32": 4}[UNITS["encoding"]]
    return len(text.encode(encoding[UNITS["encoding"]])) // size


def at(text: str, needle: str, nth: int = 0, offset: int = 0) -> types.Position:
    """The position of the ``nth`` occurrence of ``needle`` (+ ``offset`` characters), in
    the code units of the negotiated encoding (UTF-16 unless the client offered another)."""
    start = -1
    for _ in range(nth + 1):
        start = text.index(needle, start + 1)
    start += offset
    line = text.count("\n", 0, start)
    column = text[text.rfind("\n", 0, start) + 1 : start]
    return types.Position(line, units(column))


def span(text: str, needle: str, nth: int = 0) -> types.Range:
    start = at(text, needle, nth)
    end = types.Position(start.line, start.character + units(needle))
    return types.Range(start, end)


async def diagnostics_of(client: LanguageClient, doc: str, version: int) -> list:
    """The diagnostics the server published for ``doc`` at ``version``."""

    async def wait():
        while True:
            got = client.diagnostics.get(doc)
            if got is not None and client.diagnostic_versions.get(doc) == version:
                return list(got)
            await asyncio.sleep(0.02)

    return await asyncio.wait_for(wait(), TIMEOUT)


async def open_doc(client: LanguageClient, path: Path, text: str | None = None, version=1):
    text = path.read_text(encoding="utf-8") if text is None else text
    language = "irl" if path.suffix == ".irl" else "toml"
    item = types.TextDocumentItem(uri=uri(path), language_id=language, version=version, text=text)
    client.text_document_did_open(types.DidOpenTextDocumentParams(item))
    return await diagnostics_of(client, uri(path), version)


async def change(client: LanguageClient, path: Path, text: str, version: int) -> list:
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri(path), version=version),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)],
        )
    )
    return await diagnostics_of(client, uri(path), version)


def close(client: LanguageClient, path: Path) -> None:
    client.text_document_did_close(
        types.DidCloseTextDocumentParams(types.TextDocumentIdentifier(uri(path)))
    )


async def complete(client, path: Path, text: str, position: types.Position):
    result = await client.text_document_completion_async(
        types.CompletionParams(types.TextDocumentIdentifier(uri(path)), position)
    )
    items = result.items if isinstance(result, types.CompletionList) else result
    return {item.label: item for item in items}


async def hover(client, path: Path, position: types.Position) -> str:
    result = await client.text_document_hover_async(
        types.HoverParams(types.TextDocumentIdentifier(uri(path)), position)
    )
    assert result is not None
    return result.contents.value


async def definition(client, path: Path, position: types.Position):
    result = await client.text_document_definition_async(
        types.DefinitionParams(types.TextDocumentIdentifier(uri(path)), position)
    )
    return result[0] if isinstance(result, list) else result
