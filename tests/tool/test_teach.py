"""Teaching (REPL ``:teach NAME [FILE]``): the data list is created or edited as text —
comments and other entries kept — and a taught pose round-trips through it."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from irlc.repl import Session
from irlc.runtime.run import run_file
from irlc.teach import TeachError, teach, upsert

CELL = """# cell of the line  (kept)
[poses]   # mm, deg
home_p = [2000, 1000, 0, 0, 0, 0]   # start
p1 = [
  1000, 1000, 0,   # a multi-line value
  0, 0, 0,
]  # old p1

[joints]
home = [0, 90, -90]

[obstacles.post]          # a sphere
kind = "sphere"
center = [1500, -300, 0]  # '#' in a comment
radius = 50

[inputs]
2 = [[0.0, false], [3.0, true]]
"""


def test_update_keeps_comments_and_other_entries(tmp_path):
    path = tmp_path / "cell.toml"
    path.write_text(CELL, encoding="utf-8")
    before = tomllib.loads(CELL)
    keys = teach(path, "p1", [1500, 500, 0, -9.9827691, 0, 0], [-12.5, 129.75, -127.25])
    assert keys == ["poses.p1", "joints.p1_joints"]
    text = path.read_text(encoding="utf-8")
    after = tomllib.loads(text)
    assert after["poses"]["p1"] == [1500, 500, 0, -9.982769, 0, 0]  # 6 decimals
    assert after["joints"]["p1_joints"] == [-12.5, 129.75, -127.25]
    for section in ("obstacles", "inputs"):
        assert after[section] == before[section]
    assert after["poses"]["home_p"] == before["poses"]["home_p"]
    assert after["joints"]["home"] == before["joints"]["home"]
    kept = [ln for ln in CELL.splitlines() if "multi-line" not in ln and "0, 0, 0," not in ln]
    kept = [ln for ln in kept if not ln.startswith(("p1 =", "]"))]
    for line in kept:  # every other line, comments included, is still there
        assert line in text.splitlines(), line
    assert "p1 = [1500, 500, 0, -9.982769, 0, 0]  # old p1" in text
    assert text.index("p1_joints") < text.index("[obstacles.post]")  # in its section


def test_new_file_and_missing_section(tmp_path):
    path = tmp_path / "new.toml"
    teach(path, "a", [1, 2, 3, 0, 0, 90], [0.5, -0.25])
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    assert data == {"poses": {"a": [1, 2, 3, 0, 0, 90]}, "joints": {"a_joints": [0.5, -0.25]}}
    assert path.read_text(encoding="utf-8").startswith("# Data list written by irlc :teach")
    only_inputs = "[inputs]\n1 = [[0.0, true]]\n"
    assert tomllib.loads(upsert(only_inputs, "poses", "b", [1.0])) == {
        "inputs": {"1": [[0.0, True]]},
        "poses": {"b": [1.0]},
    }


@pytest.mark.parametrize(
    "text",
    ["poses = { p = [1, 2, 3, 0, 0, 0] }\n", "[poses\np = 1\n", "poses = 3\n"],
    ids=["inline table", "bad toml", "not a table"],
)
def test_unsuitable_files_are_left_alone(tmp_path, text):
    path = tmp_path / "x.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(TeachError, match="nothing written"):
        teach(path, "p", [0, 0, 0, 0, 0, 0], [0, 0, 0])
    assert path.read_text(encoding="utf-8") == text


def test_bad_names(tmp_path):
    with pytest.raises(TeachError, match="not a name"):
        teach(tmp_path / "x.toml", "1p", [0] * 6, [0] * 3)
    session = Session("planar3", cwd=tmp_path)
    session.enter("VAR POSE: q;")
    assert session.meta(":teach q").failure == 3
    assert session.meta(":teach LIN").failure == 3
    assert session.meta(":teach R_SPEED").failure == 3  # a system variable
    assert session.meta(":teach").lines == ["<input>:1:1: error: usage: :teach NAME [FILE.toml]"]
    assert not (tmp_path / "taught.toml").exists()


@pytest.mark.parametrize("where", ["/", ".", "..", "sub/", "~"])
def test_a_folder_is_not_a_teach_file(tmp_path, where):
    # ':teach a /' printed Python's "PosixPath('/') has an empty name"; '.' wrote '../NAME.toml'
    (tmp_path / "sub").mkdir()
    session = Session("planar3", cwd=tmp_path)
    out = session.meta(f":teach a {where}")
    assert out.failure == 3
    assert out.lines == [
        f"<input>:1:1: error: {where} is a folder; :teach takes a file (FILE.toml)"
    ]
    assert list(tmp_path.parent.glob("*.toml")) == list(tmp_path.glob("**/*.toml")) == []


def test_a_name_beside_a_folder_of_that_name_is_its_toml_file(tmp_path):
    """Regression: after the README's `mkdir -p cell`, the tutorial's `:teach corner cell`
    said "cell is a folder" — but the file is cell.toml (`.toml` added to a bare name)."""
    (tmp_path / "cell").mkdir()
    (tmp_path / "box.toml").mkdir()
    session = Session("planar3", cwd=tmp_path)
    assert session.meta(":teach corner cell").failure == 0
    assert "corner" in (tmp_path / "cell.toml").read_text(encoding="utf-8")
    out = session.meta(":teach corner box")
    assert out.failure == 3
    assert out.lines == [
        f"<input>:1:1: error: {tmp_path / 'box.toml'} is a folder; :teach takes a file (FILE.toml)"
    ]


def test_taught_pose_round_trips(tmp_path):
    (tmp_path / "cell.toml").write_text(CELL, encoding="utf-8")
    session = Session("planar3", cwd=tmp_path)
    for entry in ("MOVE PTP (10, 80, -60);", "MOVE LIN POSE(1500, 500, 0, 0, 0, 0);"):
        assert session.enter(entry).failure == 0
    out = session.meta(":teach spot cell")
    assert out.failure == 0 and "poses.spot, joints.spot_joints" in out.lines[0]
    taught_q = np.array(session._program_units(session.controller.q))
    (tmp_path / "back.irl").write_text(
        "PROGRAM back;\nROBOT r := planar3;\nIMPORT DATALIST cell;\nBEGIN\n"
        "  MOVE PTP home;\n  MOVE LIN spot;\n  WRITELN(R_ACT_POSE.x, ' ', R_ACT_POSE.y);\n"
        "  MOVE PTP home;\n  MOVE PTP spot_joints;\nENDPROGRAM\n",
        encoding="utf-8",
    )
    run = run_file(tmp_path / "back.irl")
    assert run.ok, run.error
    x, y = (float(v) for v in run.output[0].split())
    assert (x, y) == pytest.approx((1500.0, 500.0), abs=1e-5)
    assert run.report["end_joints"] == pytest.approx(taught_q, abs=1e-6)


# --------------------------------------------------------------------------- property


def _section_text(draw, st, section: str, names: list[str]) -> list[str]:
    lines = [f"[{section}]" + draw(st.sampled_from(["", "   # " + section]))]
    for name in names:
        values = draw(st.lists(st.integers(-999, 999), min_size=1, max_size=6))
        text = ", ".join(map(str, values))
        if draw(st.booleans()):
            lines.append(f"{name} = [{text}]" + draw(st.sampled_from(["", "  # c"])))
        else:  # a multi-line array
            lines += [f"{name} = [", f"  {text},  # inside", "]"]
        lines += draw(st.sampled_from([[], [""], ["# between"]]))
    return lines


def test_teach_keeps_every_other_line_of_generated_files(tmp_path):
    from hypothesis import given, settings
    from hypothesis import strategies as st

    names = st.lists(st.sampled_from(["a", "b", "p1", "home"]), unique=True, max_size=3)

    @st.composite
    def files(draw):
        sections = draw(st.permutations(["poses", "joints", "inputs"]))
        lines = draw(st.sampled_from([[], ["# header", ""]]))
        for section in sections[: draw(st.integers(0, 3))]:
            if section == "inputs":
                lines += ["[inputs]", '1 = [[0.0, false], [2.5, true]]  # "#" too', ""]
            else:
                lines += _section_text(draw, st, section, draw(names))
        return "\n".join(lines) + ("\n" if lines else "")

    @settings(max_examples=60, deadline=None)
    @given(files(), st.sampled_from(["a", "p1", "new_one"]))
    def check(text, name):
        path = tmp_path / "gen.toml"
        path.write_text(text, encoding="utf-8")
        teach(path, name, [1.5, -2, 3, 0, 90, -180], [10, -20.25, 30])
        new = path.read_text(encoding="utf-8")
        data = tomllib.loads(new)
        assert data["poses"][name] == [1.5, -2, 3, 0, 90, -180]
        assert data["joints"][name + "_joints"] == [10, -20.25, 30]
        old_lines = [ln for ln in text.splitlines() if ln.startswith(("#", "[", "1 ="))]
        for line in old_lines:  # headers, comments and other entries are all still there
            assert line in new.splitlines()

    check()


def test_repl_cycle_time_does_not_read_a_foreign_repl_irl(tmp_path):
    (tmp_path / "repl.irl").write_text("something else\n" * 20, encoding="utf-8")
    session = Session("planar3", cwd=tmp_path)
    assert session.enter("MOVE LIN POSE(1500, 1000, 0, 0, 0, 0);").failure == 0
    rows = session.run_result().report["statements"]
    assert [r["statement"] for r in rows] == ["MOVE LIN"]
