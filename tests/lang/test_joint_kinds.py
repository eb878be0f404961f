"""The one joint-kind owner (lang/joint_kinds.py): word ↔ IRDATA letter, both ways."""

from __future__ import annotations

import pytest
from irlc.lang import joint_kinds as K
from irlc.lang.signature import SimpleRobot, kind_letters


def test_words_and_letters_round_trip():
    for kind in K.KINDS:
        assert K.kind_from_letter(K.kind_letter(kind)) == kind
    assert K.kind_letters(["revolute", "prismatic", "R"]) == "RPR"
    assert [K.is_revolute(k) for k in ("revolute", "prismatic", "R", "P")] == [1, 0, 1, 0]


@pytest.mark.parametrize("bad", ["", "x", "spherical"])
def test_an_unknown_kind_is_refused_with_its_name(bad):
    with pytest.raises(ValueError, match="unknown joint kind"):
        K.kind_letter(bad)
    with pytest.raises(ValueError, match=r"robot r: unknown joint kind 'spherical'"):
        kind_letters(SimpleRobot("r", ("revolute", "spherical")))
    with pytest.raises(ValueError, match="unknown joint kind letter"):
        K.kind_from_letter(bad.upper()[:1] or "Q")
