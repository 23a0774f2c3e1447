"""Annotation fields of a case record (issue 34, item 5): ``why``, ``comment``, ``note`` and ``source``
are strings for people, accepted and not read by the rule; any other unknown field is refused."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from tests.helpers import cradle_case
from verify.cli import main
from verify.errors import InvalidInput
from verify.records.results import ANNOTATION_FIELDS, case_from_record, load_cases
from verify.records.schema import schema


def case(**extra: Any) -> dict[str, Any]:
    return {**cradle_case("c", ["1", "1", "1"], ["1/2", "1/2"], ["1", "0", "0"]), **extra}


def write(tmp_path: Path, record: dict[str, Any]) -> Path:
    path = tmp_path / "cases.json"
    path.write_text(json.dumps({"cases": [record]}), encoding="utf-8")
    return path


def test_the_schema_and_the_loader_know_the_same_annotation_fields() -> None:
    props = schema("case")["$defs"]["case"]["properties"]
    assert ANNOTATION_FIELDS == ("why", "comment", "note", "source")
    assert {f for f, s in props.items() if s.get("$ref") == "#/$defs/annotation"} == set(ANNOTATION_FIELDS)


@pytest.mark.parametrize("name", ANNOTATION_FIELDS)
def test_every_annotation_field_is_accepted_and_not_read(tmp_path: Path, name: str, capsys: Any) -> None:
    plain = write(tmp_path, case())
    assert main(["solve", str(plain), "--json"]) == 0
    bare = json.loads(capsys.readouterr().out)
    annotated = write(tmp_path, case(**{name: "made by hand, 2026 (see the notebook)"}))
    (c,) = load_cases(str(annotated))
    assert c.id == "c"
    assert main(["solve", str(annotated), "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == bare  # the result does not depend on it


def test_an_unknown_field_is_still_refused(tmp_path: Path, capsys: Any) -> None:
    path = write(tmp_path, case(comments="a typo of comment"))
    assert main(["solve", str(path)]) == 2
    assert capsys.readouterr().err == f"verify: error: {path}: cases[0]: unknown field 'comments'\n"
    with pytest.raises(InvalidInput, match=r"^case: unknown field 'comments'$"):
        case_from_record(case(comments="x"))


def test_an_annotation_that_is_not_a_string_is_refused(tmp_path: Path, capsys: Any) -> None:
    path = write(tmp_path, case(comment=["two", "lines"]))
    assert main(["solve", str(path)]) == 2
    assert capsys.readouterr().err == f"verify: error: {path}: cases[0].comment: expected a string, got list\n"
    with pytest.raises(InvalidInput, match=r"^case\.note: an annotation is a string, got int$"):
        case_from_record(case(note=7))
