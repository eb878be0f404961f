"""Language-server latency: a 1,000-line program edited in an editor (issue 28's goal:
diagnostics within ~200 ms of a change).

Two measurements of the same program (``bench_compile.program``: declarations, routines,
control flow, motion, redundancy blocks; one statement a line):

* over stdio, as an editor sees it: ``irlc lsp`` started as a subprocess, a pygls client
  opens the program, then sends ``--edits`` one-character changes (a number of one line,
  the whole text each time, as VS Code sends it with full sync) and times each change →
  its ``publishDiagnostics``; then hover and completion requests (the first of them builds
  the index);
* in process, the parts: the compile (:func:`irlc.lsp.analysis.ProgramAnalysis.of`), the
  index, the same with a half-typed line (a syntax error: the index is built from the text
  with that line blanked).

    python bench/bench_lsp.py [--lines 1000] [--edits 30]
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from bench_compile import program
from irlc.lsp.analysis import ProgramAnalysis, Settings
from lsprotocol import types
from pygls.lsp.client import LanguageClient
from pygls.uris import from_fs_path


def edited(text: str, k: int) -> str:
    """``text`` with one digit changed (the ``k``-th edit): a keystroke in a line."""
    return text.replace("  x := 0; y := 0;", f"  x := {k % 10}; y := 0;", 1)


def summary(samples_ms: list[float]) -> str:
    s = sorted(samples_ms)
    p90 = s[min(len(s) - 1, int(0.9 * len(s)))]
    return f"median {statistics.median(s):.0f} ms, p90 {p90:.0f} ms, max {s[-1]:.0f} ms"


async def over_stdio(path: Path, text: str, edits: int) -> dict[str, str]:
    client = LanguageClient("bench-lsp", "1")
    published: dict[int, asyncio.Future] = {}

    @client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diagnostics(params: types.PublishDiagnosticsParams) -> None:
        future = published.get(params.version)
        if future is not None and not future.done():
            future.set_result(params.diagnostics)

    irlc = Path(sys.executable).parent / "irlc"
    await client.start_io(str(irlc), "lsp")
    await client.initialize_async(types.InitializeParams(capabilities=types.ClientCapabilities()))
    client.initialized(types.InitializedParams())
    uri = from_fs_path(str(path))
    loop = asyncio.get_running_loop()

    published[1] = loop.create_future()
    start = time.perf_counter()
    client.text_document_did_open(types.DidOpenTextDocumentParams(
        types.TextDocumentItem(uri=uri, language_id="irl", version=1, text=text)))  # fmt: skip
    diagnostics = await published[1]
    opened = (time.perf_counter() - start) * 1000
    assert not diagnostics, diagnostics  # the generated program compiles

    changes = []
    for k in range(2, edits + 2):
        published[k] = loop.create_future()
        start = time.perf_counter()
        client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=k),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=edited(text, k))],
        ))  # fmt: skip
        await published[k]
        changes.append((time.perf_counter() - start) * 1000)

    doc = types.TextDocumentIdentifier(uri)
    line = text.splitlines().index("  MOVE LIN p WITH SPEED := 500;")
    where = types.Position(line, 13)
    requests = {}
    for name, call in (
        ("hover (first: builds the index)", lambda: client.text_document_hover_async(
            types.HoverParams(doc, where))),
        ("hover", lambda: client.text_document_hover_async(types.HoverParams(doc, where))),
        ("completion", lambda: client.text_document_completion_async(
            types.CompletionParams(doc, types.Position(line, 2)))),
        ("definition", lambda: client.text_document_definition_async(
            types.DefinitionParams(doc, where))),
    ):  # fmt: skip
        start = time.perf_counter()
        await call()
        requests[name] = f"{(time.perf_counter() - start) * 1000:.0f} ms"
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return {"open → diagnostics": f"{opened:.0f} ms",
            f"change → diagnostics ({edits} edits)": summary(changes), **requests}  # fmt: skip


def in_process(path: Path, text: str, repeat: int) -> dict[str, str]:
    settings = Settings()
    compile_ms, index_ms, recovered_ms = [], [], []
    half_typed = text.replace("  MOVE LIN p WITH SPEED := 500;", "  MOVE LIN p WITH SPEED :=", 1)
    for k in range(repeat):
        start = time.perf_counter()
        analysis = ProgramAnalysis.of(path, edited(text, k), settings, {})
        compile_ms.append((time.perf_counter() - start) * 1000)
        start = time.perf_counter()
        assert analysis.index() is not None
        index_ms.append((time.perf_counter() - start) * 1000)
        broken = ProgramAnalysis.of(path, half_typed, settings, {})
        start = time.perf_counter()
        assert broken.index() is not None
        recovered_ms.append((time.perf_counter() - start) * 1000)
    return {"compile (diagnostics)": summary(compile_ms), "index": summary(index_ms),
            "index of a half-typed text": summary(recovered_ms)}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lines", type=int, default=1000)
    ap.add_argument("--edits", type=int, default=30)
    args = ap.parse_args()
    text = program(args.lines)
    print(f"{len(text.splitlines())} lines, {len(text)} characters; "
          f"load average {os.getloadavg()[0]:.2f}")  # fmt: skip
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bench.irl"
        path.write_text(text, encoding="utf-8")
        rows = asyncio.run(over_stdio(path, text, args.edits))
        rows |= in_process(path, text, max(5, args.edits // 3))
    width = max(len(k) for k in rows)
    for name, value in rows.items():
        print(f"{name:<{width}}  {value}")
    print(f"load average after {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
