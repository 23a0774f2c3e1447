"""The versions a document of the oracle carries: its schema's, and the dataset its cases come from.

Every case file, result file and ``--json`` document that ``verify oracle`` writes starts with
``"schema_version"`` (:data:`SCHEMA_VERSION`) and, where its cases come from a named set, ``"dataset"``
(the golden dataset is :data:`GOLDEN_DATASET`; ``verify oracle generate`` names its level, seed and law).
Both are checked when a file is read (:func:`check_versions`): a schema newer than this ``verify`` reads
is refused, and so is a result file made for another dataset than its case file. A file without them
(one written by hand, or by another implementation) is read as the current schema.

>>> stamped({"cases": []}, "golden-2")
{'schema_version': 2, 'dataset': 'golden-2', 'cases': []}
>>> check_versions({"schema_version": 3, "cases": []}, "new.json")
Traceback (most recent call last):
...
verify.errors.InvalidInput: new.json: schema_version 3 is newer than this verify reads (1 to 2): upgrade verify
"""

from __future__ import annotations

from typing import Any

from verify.errors import InvalidInput

#: the schema of the oracle's JSON documents: 1 before these fields existed, 2 since verify 0.2.0
SCHEMA_VERSION = 2
#: the golden dataset's version (``verify oracle export``): raised when its cases, their exact results or its
#: files' format change (2: the files carry schema_version and dataset, and name no rational library)
GOLDEN_VERSION = 2
GOLDEN_DATASET = f"golden-{GOLDEN_VERSION}"


def stamped(document: dict[str, Any], dataset: str | None = None, *, report: bool = False) -> dict[str, Any]:
    """``document`` with ``schema_version`` and ``dataset`` first: a case or result file names its dataset when
    it has one; a ``report`` (a ``--json`` document) always has the field (null: the case file names none).

    >>> stamped({"table": []}, None, report=True)
    {'schema_version': 2, 'dataset': None, 'table': []}
    """
    head: dict[str, Any] = {"schema_version": SCHEMA_VERSION}
    if dataset is not None or report:
        head["dataset"] = dataset
    return {**head, **{k: v for k, v in document.items() if k not in ("schema_version", "dataset")}}


#: the version of ``verify oracle generate``'s cases: raised whenever the same level and seed give other cases
GENERATOR_VERSION = 1


def generated_dataset(level: int, seed: int, law: str = "rule") -> str:
    """The dataset name of ``verify oracle generate --level L --seed S [--law LAW]``.

    >>> generated_dataset(1, 0), generated_dataset(2, 7, "sequential")
    ('generated-v1-level-1-seed-0', 'generated-v1-level-2-seed-7-sequential')
    """
    return f"generated-v{GENERATOR_VERSION}-level-{level}-seed-{seed}" + ("" if law == "rule" else f"-{law}")


def check_versions(data: Any, source: str) -> str | None:
    """Check the versions of a document read from ``source``; returns its dataset (None when not named)."""
    if not isinstance(data, dict):
        return None
    version = data.get("schema_version", SCHEMA_VERSION)
    if type(version) is not int or version < 1:
        raise InvalidInput(f"{source}: schema_version must be a positive integer, got {version!r}")
    if version > SCHEMA_VERSION:
        raise InvalidInput(
            f"{source}: schema_version {version} is newer than this verify reads (1 to {SCHEMA_VERSION}): "
            "upgrade verify"
        )
    dataset = data.get("dataset")
    if dataset is not None and not isinstance(dataset, str):
        raise InvalidInput(f"{source}: dataset must be a string, got {dataset!r}")
    return dataset


def check_same_dataset(cases: str | None, results: str | None, results_source: str) -> None:
    """A result file made for another dataset than the case file's is refused (both named).

    >>> check_same_dataset("golden-2", "golden-1", "old.json")
    Traceback (most recent call last):
    ...
    verify.errors.InvalidInput: old.json: made for dataset golden-1, but the case file is golden-2: ...
    """
    if cases is not None and results is not None and cases != results:
        raise InvalidInput(
            f"{results_source}: made for dataset {results}, but the case file is {cases}: check the results "
            "of these cases (verify oracle export writes both)"
        )
