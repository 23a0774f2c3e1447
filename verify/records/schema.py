"""JSON Schemas (draft 2020-12) of the case and result files, shipped with the package.

``verify/records/schemas/case.schema.json`` and ``result.schema.json`` describe the files of the
contracts; :func:`validate` checks a parsed file against one of them and raises
:class:`~verify.errors.InvalidInput` naming the first offending field the way the rest of
the loader does (``cases[3].normals[1]: expected a string, got 7``). Numbers are then
read by the restricted parser, which the schema cannot express.

>>> validate({"cases": [{"id": "a", "mass_matrix": [["1"]], "normals": [["1"]],
...                      "restitution": ["1/2"], "velocity": [7]}]}, "case")
Traceback (most recent call last):
...
verify.errors.InvalidInput: cases[0].velocity[0]: expected a string, got 7
"""

from __future__ import annotations

import json
from functools import cache
from importlib import resources
from typing import Any

from verify.errors import InvalidInput

KINDS = ("case", "result")


@cache
def schema(kind: str) -> dict[str, Any]:
    """The schema of a case file (``"case"``) or a result file (``"result"``)."""
    if kind not in KINDS:
        raise ValueError(f"unknown schema {kind!r}")
    text = resources.files("verify.records").joinpath("schemas", f"{kind}.schema.json").read_text(encoding="utf-8")
    schema: dict[str, Any] = json.loads(text)
    return schema


@cache
def _validator(kind: str) -> Any:
    from jsonschema import Draft202012Validator

    Draft202012Validator.check_schema(schema(kind))
    return Draft202012Validator(schema(kind))


def path_string(path: Any) -> str:
    """``["cases", 3, "normals", 1]`` as ``cases[3].normals[1]``."""
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "(top level)"


def _describe(value: Any) -> str:
    text = getattr(value, "json_number_text", None)  # a bare JSON number kept as text by the loader
    if text is not None:
        return f'the bare number {text} (numbers are strings: write "{text}")'
    constant = getattr(value, "json_constant_text", None)  # a bare NaN or Infinity kept by the loader
    if constant is not None:
        return f"the bare JSON constant {constant} (not a number; numbers are strings)"
    shown = json.dumps(value) if isinstance(value, (str, int, bool, type(None))) else type(value).__name__
    return shown if len(shown) <= 60 else shown[:57] + "..."


_TYPES = {"string": "a string", "array": "a list", "object": "an object", "integer": "an integer", "null": "null"}


def _message(error: Any) -> str:
    where = path_string(error.absolute_path)
    if error.validator == "type":
        expected = _TYPES.get(error.validator_value, error.validator_value)
        return f"{where}: expected {expected}, got {_describe(error.instance)}"
    if error.validator == "required":
        missing = next(f for f in error.validator_value if f not in error.instance)
        return f"{where}: missing field {missing!r}"
    if error.validator == "additionalProperties":
        extra = sorted(set(error.instance) - set(error.schema.get("properties", {})))
        return f"{where}: unknown field {extra[0]!r}"
    if error.validator in ("maxItems", "maxLength"):
        return f"{where}: too long (at most {error.validator_value})"
    if error.validator in ("minItems", "minLength"):
        return f"{where}: empty"
    if error.validator == "uniqueItems":
        seen = [x for i, x in enumerate(error.instance) if x in error.instance[:i]]
        return f"{where}: {_describe(seen[0])} appears twice (the entries must be unique)"
    if error.validator == "enum":
        return f"{where}: {_describe(error.instance)} is not one of {', '.join(map(str, error.validator_value))}"
    return f"{where}: {error.message}"


def validate(data: Any, kind: str, source: str = "") -> None:
    """Raise :class:`InvalidInput` for the first schema violation in document order
    (the message is prefixed by ``source``, say the file name)."""
    errors = list(_validator(kind).iter_errors(data))
    if errors:
        first = min(
            errors, key=lambda e: [(0, p, "") if isinstance(p, int) else (1, 0, str(p)) for p in e.absolute_path]
        )
        raise InvalidInput((f"{source}: " if source else "") + _message(first))
