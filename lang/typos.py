"""Misspelled keywords: the END_IF / ELSEIF family and the one diagnostic that names them.

IRL writes its block ends as one word (ENDIF, ENDPROC, CYCLICEND, …) and ELSIF; other
dialects and habits write ``END_IF``, ``ELSEIF``, ``ENDPROCEDURE``. These parse as names,
so the parser sees a call or an unexpected token; :func:`misspelled_keyword` turns the word
into "'END_IF' is not a keyword of this dialect — write ENDIF" at the word itself.
"""

from __future__ import annotations

from irlc.lang.diagnostics import Diagnostic, Span

MISSPELLED = {
    "ELSEIF": "ELSIF",
    "ELIF": "ELSIF",
    "ENDPROCEDURE": "ENDPROC",
    "ENDFUNCTION": "ENDFCT",
    "ENDFUNC": "ENDFCT",
    "END_IF": "ENDIF",
    "END_WHILE": "ENDWHILE",
    "END_FOR": "ENDFOR",
    "END_CASE": "ENDCASE",
    "END_PROC": "ENDPROC",
    "END_PROCEDURE": "ENDPROC",
    "END_FCT": "ENDFCT",
    "END_FUNCTION": "ENDFCT",
    "END_PROGRAM": "ENDPROGRAM",
    "CYCLIC_START": "CYCLICSTART",
    "CYCLIC_END": "CYCLICEND",
    "FREEZE_START": "FREEZESTART",
    "FREEZE_END": "FREEZEEND",
    "JOINTLIMIT_END": "JOINTLIMITEND",
    "JOINTSPEEDLIMIT_END": "JOINTSPEEDLIMITEND",
    "JOINTACCELLIMIT_END": "JOINTACCELLIMITEND",
    "OBSTACLE_END": "OBSTACLEEND",
    "ENDCYCLIC": "CYCLICEND",
    "COOPERATE_END": "COOPERATEEND",
    "END_COOPERATE": "COOPERATEEND",
    "ENDCOOPERATE": "COOPERATEEND",
    "COOPERATEND": "COOPERATEEND",
}
"""A misspelling (upper case) → the keyword meant."""


def misspelled_keyword(word: str, span: Span, filename: str) -> Diagnostic | None:
    """The error for ``word`` at ``span`` if it misspells a keyword, else ``None``."""
    meant = MISSPELLED.get(word.upper())
    if meant is None:
        return None
    return Diagnostic(
        "error", f"'{word}' is not a keyword of this dialect", filename, span, f"write {meant}"
    )
