"""The language server (pygls): documents in, diagnostics and answers out.

Documents are IRL programs (``*.irl``) and data lists (``*.toml``). Each open program is
analysed on open and on every change (:class:`~irlc.lsp.analysis.ProgramAnalysis`), with
the unsaved text of every open data list in place of its file; a change of a data list
analyses the open programs again. Diagnostics go to the program, and to each open data
list the programs import. A ``.toml`` no open program imports is checked on its own
(without the robot's joint count) when its tables are all data-list sections; any other
TOML file (a robot file, ``pyproject.toml``) gets no diagnostics from this server.

Requests — completion, hover, go to definition, document symbols — read the index of the
program's latest analysis. Nothing rewrites the user's text: the server offers no
formatting and no edits.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from irlc import __version__
from irlc.lang import datalist as dlmod
from irlc.lang.diagnostics import Span
from irlc.lsp import completion, diagnostics, hover, navigation
from irlc.lsp.analysis import ProgramAnalysis, Settings
from irlc.lsp.positions import SourceLines
from lsprotocol import types
from pygls.capabilities import get_capability
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path, to_fs_path

NAME = "irlc"


class IrlServer(LanguageServer):
    """The server's state: the compile settings and the open programs' analyses."""

    def __init__(self, settings: Settings):
        super().__init__(NAME, __version__, text_document_sync_kind=types.TextDocumentSyncKind.Full)
        self.settings = settings
        self.programs: dict[str, ProgramAnalysis] = {}  # uri → latest analysis

    # ------------------------------------------------------------------ documents
    def text(self, uri: str) -> str:
        return self.workspace.get_text_document(uri).source

    def lines(self, text: str) -> SourceLines:
        return SourceLines(text, self.workspace.position_codec)

    def open_uris(self) -> list[str]:
        return list(self.workspace.text_documents)

    def datalist_texts(self) -> dict[str, str]:
        """The open data lists' texts by resolved path (read instead of their files)."""
        return {str(path_of(uri).resolve()): self.text(uri)
                for uri in self.open_uris() if is_datalist(uri)}  # fmt: skip

    def analyze(self, uri: str) -> None:
        previous = self.programs.get(uri)
        self.programs[uri] = ProgramAnalysis.of(
            path_of(uri), self.text(uri), self.settings, self.datalist_texts(), previous
        )

    def refresh(self, changed: str) -> None:
        """Analyse what ``changed`` affects and publish every open document's diagnostics."""
        if is_program(changed):
            self.analyze(changed)
        else:  # a data list: every open program may import it
            for uri in self.open_uris():
                if is_program(uri):
                    self.analyze(uri)
        for uri in self.open_uris():
            if is_program(uri):
                self.publish_program(uri)
            elif is_datalist(uri):
                self.publish_datalist(uri)

    def publish(self, uri: str, found: list[types.Diagnostic]) -> None:
        version = self.workspace.get_text_document(uri).version
        params = types.PublishDiagnosticsParams(uri=uri, diagnostics=found, version=version)
        self.text_document_publish_diagnostics(params)

    def publish_program(self, uri: str) -> None:
        program = self.programs.get(uri)
        if program is None:
            return
        clauses = {}
        if program.checked is not None:
            names = {c.name.lower(): c for c in program.checked.program.datalists}
            clauses = {dl.path: names[dl.name.lower()] for dl in program.checked.datalists
                       if dl.name.lower() in names}  # fmt: skip
        related = self.supports("text_document.publish_diagnostics.related_information")
        found = diagnostics.program_diagnostics(
            program.diagnostics, program.path, self.lines(program.text), clauses,
            self.diagnostic_location if related else None,
        )  # fmt: skip
        self.publish(uri, found)

    def publish_datalist(self, uri: str) -> None:
        path = path_of(uri)
        lines = self.lines(self.text(uri))
        importers = [p for p in self.programs.values() if p.checked is not None
                     and any(Path(d.path).resolve() == path.resolve()
                             for d in p.checked.datalists)]  # fmt: skip
        if importers:
            found = [d for p in importers for d in p.diagnostics]
        elif looks_like_datalist(self.text(uri)):  # on its own: no joint count to check
            _, found = dlmod.load(path.stem, path, path.parent, None, self.text(uri))
        else:  # another TOML file (a robot file, pyproject.toml): not the server's
            found = []
        self.publish(uri, diagnostics.datalist_diagnostics(found, path, lines))

    def diagnostic_location(self, d) -> types.Location | None:
        return self.locate(Path(d.file), d.span)

    def locate(self, path: Path, span: Span | None) -> types.Location:
        """A place in a file, converted with its text (the open buffer, else the file)."""
        uri = from_fs_path(str(path)) or str(path)
        doc = self.workspace.text_documents.get(uri)
        if doc is not None:
            text = doc.source
        else:
            try:
                text = path.read_text(encoding="utf-8", errors="replace")
            except OSError:
                text = ""
        return types.Location(uri=uri, range=self.lines(text).range(span))

    def supports(self, capability: str, default=False):
        return get_capability(self.client_capabilities, capability, default)


def looks_like_datalist(text: str) -> bool:
    """A TOML text whose tables are all data-list sections (``[poses]``, …)."""
    try:
        doc = tomllib.loads(text)
    except (tomllib.TOMLDecodeError, ValueError):
        return False
    return bool(doc) and set(doc) <= set(dlmod.SECTIONS)


def path_of(uri: str) -> Path:
    """The file of a document (an unsaved one: a name in the working folder)."""
    path = to_fs_path(uri) if uri.startswith("file:") else None
    return Path(path) if path else Path.cwd() / "untitled.irl"


def is_program(uri: str) -> bool:
    return uri.lower().endswith(".irl") or not uri.startswith("file:")


def is_datalist(uri: str) -> bool:
    return uri.lower().endswith(".toml") and uri.startswith("file:")


def make_server(settings: Settings) -> IrlServer:
    server = IrlServer(settings)

    @server.feature(types.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: IrlServer, params: types.DidOpenTextDocumentParams) -> None:
        ls.refresh(params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: IrlServer, params: types.DidChangeTextDocumentParams) -> None:
        ls.refresh(params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_SAVE)
    def did_save(ls: IrlServer, params: types.DidSaveTextDocumentParams) -> None:
        ls.refresh(params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: IrlServer, params: types.DidCloseTextDocumentParams) -> None:
        uri = params.text_document.uri
        ls.programs.pop(uri, None)
        ls.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=uri, diagnostics=[])
        )
        if is_datalist(uri):  # the programs read its file again
            ls.refresh(uri)

    @server.feature(
        types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=["."])
    )
    def on_completion(ls: IrlServer, params: types.CompletionParams):
        program = ls.programs.get(params.text_document.uri)
        if program is None:
            return None
        lines = ls.lines(ls.text(params.text_document.uri))
        line, column = lines.cursor(params.position)
        formats = ls.supports("text_document.completion.completion_item.documentation_format", [])
        context = completion.Context(
            program.path, lines.before(line, column), line, ls.settings.datalist_path,
            snippets=ls.supports("text_document.completion.completion_item.snippet_support"),
            markdown=types.MarkupKind.Markdown in (formats or []),
        )  # fmt: skip
        items = completion.complete(context, program.names_index(line))
        return types.CompletionList(is_incomplete=False, items=items)

    @server.feature(types.TEXT_DOCUMENT_HOVER)
    def on_hover(ls: IrlServer, params: types.HoverParams):
        found = _target(ls, params)
        if found is None:
            return None
        program, index, occurrence = found
        text = hover.hover_text(occurrence.target, index, program.path,
                                ls.settings.allow_any_path, occurrence.robot)  # fmt: skip
        if text is None:
            return None
        formats = ls.supports("text_document.hover.content_format", []) or []
        kind = types.MarkupKind.Markdown if types.MarkupKind.Markdown in formats else (
            types.MarkupKind.PlainText)  # fmt: skip
        lines = ls.lines(program.text)
        return types.Hover(types.MarkupContent(kind, text), lines.range(occurrence.span))

    @server.feature(types.TEXT_DOCUMENT_DEFINITION)
    def on_definition(ls: IrlServer, params: types.DefinitionParams):
        found = _target(ls, params)
        if found is None:
            return None
        program, _, occurrence = found
        return navigation.definition(
            occurrence.target, program.path, ls.settings.datalist_path,
            ls.settings.allow_any_path, ls.locate,
        )  # fmt: skip

    @server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    def on_symbols(ls: IrlServer, params: types.DocumentSymbolParams):
        program = ls.programs.get(params.text_document.uri)
        if program is None:
            return None
        tree = program.analysis.program
        index = program.index()
        if tree is None and index is not None:
            tree = index.program  # the text parsed with its half-typed lines blanked
        if tree is None:
            return []
        return navigation.document_symbols(tree, ls.lines(program.text).range)

    return server


def _target(ls: IrlServer, params):
    """The program, its index and the occurrence at the request's position, or None."""
    program = ls.programs.get(params.text_document.uri)
    index = program.index() if program is not None else None
    if program is None or index is None:
        return None
    line, column = ls.lines(program.text).cursor(params.position)
    occurrence = index.at(line, column)
    return None if occurrence is None else (program, index, occurrence)


def serve(settings: Settings) -> None:
    """Speak LSP on the standard input and output until the client says exit."""
    make_server(settings).start_io()
