"""The user documentation (docs/) ships with the project and stays true.

- No file of the project points at a documentation folder outside the repository (a
  user's clone has only what is in it).
- Every relative link of README.md and docs/*.md leads to a file that exists, and every
  ``#anchor`` to a heading of that file.
- The worked example of docs/records.md is the real, current output of ``verify solve``.
- Every command output printed in docs/*.md (a ``$ verify ...`` line in a fenced block) is what the
  program prints now (rerun here; those not run are listed in NOT_RUN, with the reason).
"""

from __future__ import annotations

import json
import re
import shlex
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from tests.helpers import bench_measured_once
from verify.cli import main

ROOT = Path(__file__).resolve().parents[2]
#: built from pieces, so that this file does not contain what it looks for
FORBIDDEN = ("shared" + "/docs", ".." + "/shared")
SCANNED = ("README.md", "docs", "verify", "tests", "examples", "golden")


def project_text_files() -> list[Path]:
    """The text files of the project's tracked folders (build output and caches left out)."""
    out = []
    for name in SCANNED:
        path = ROOT / name
        candidates = [path] if path.is_file() else sorted(p for p in path.rglob("*") if p.is_file())
        for p in candidates:
            if "__pycache__" in p.parts or p.suffix in (".pyc", ".png", ".pdf"):
                continue
            try:
                p.read_text(encoding="utf-8")
            except UnicodeDecodeError:
                continue  # not text
            out.append(p)
    return out


def test_the_scan_sees_the_project():
    """A guard for the next test: it must look at the files that matter."""
    names = {p.relative_to(ROOT).as_posix() for p in project_text_files()}
    assert {
        "README.md",
        "docs/README.md",
        "docs/records.md",
        "verify/cli/__init__.py",
        "tests/package/test_docs.py",
    } <= names


def test_no_file_points_outside_the_repository():
    found = [
        f"{p.relative_to(ROOT)}:{i}: {line.strip()}"
        for p in project_text_files()
        for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
        if any(bad in line for bad in FORBIDDEN)
    ]
    assert not found, "these lines point at a folder that users do not have:\n" + "\n".join(found)


# -- no path of the machine the files were made on ------------------------------------------------

#: the folders of users and checkouts on the machines this project is made on, built from pieces so that
#: this file does not contain them: no file of the project may hold such a path (a program's output
#: copied into a page brings them in, as python3's "can't open file" message did)
MACHINE_DIRS = ("work", "root", "home", "Users")
_MACHINE_PATH = re.compile(r"(?<![\w.~-])/(?:" + "|".join(MACHINE_DIRS) + r")/[\w.-]")
_TMP_PATH = re.compile(r"(?<![\w.~-])/" + "tmp" + r"/[\w.-]+")
#: where a path of /tmp is a path of the machine: the pages and data a user reads (tests and code use
#: temporary folders legitimately)
USER_FACING = ("README.md", "docs", "golden", "examples")


def machine_paths(text: str, rel: str) -> list[str]:
    """The lines of a file (``rel``, relative to the root) that hold an absolute path of a machine: a
    user's or checkout's folder, or, in the pages and data a user reads, a temporary folder that no
    command shown in the file was given (a transcript may show a folder its own command names:
    ``$ verify report --out /tmp/x``)."""
    given = {
        m.group(0) for line in text.splitlines() if line.lstrip().startswith("$ ") for m in _TMP_PATH.finditer(line)
    }
    user_facing = any(rel == d or rel.startswith(d + "/") for d in USER_FACING)
    found = []
    for i, line in enumerate(text.splitlines(), 1):
        tmp = [m.group(0) for m in _TMP_PATH.finditer(line)] if user_facing else []
        if _MACHINE_PATH.search(line) or any(t not in given for t in tmp):
            found.append(f"{rel}:{i}: {line.strip()}")
    return found


def test_the_path_finder_finds_what_it_looks_for() -> None:
    """A guard for the next test, on lines like the one that slipped in before (issue 34, item 8)."""
    bad = "verify: error: python3: can't open file '/" + "work/main/no_such_solver.py'"
    assert machine_paths(bad, "docs/x.md") == [f"docs/x.md:1: {bad}"]
    assert machine_paths("at /" + "home/ann/verify/x.py", "verify/x.py") != []
    assert machine_paths("see docs/work/x and ./root/y and https://example.org/home/", "docs/x.md") == []
    transcript = "\n".join(["$ verify report --out /" + "tmp/run/reports", "reports written to /" + "tmp/run/reports/",
                            "wrote /" + "tmp/elsewhere/x.json"])  # fmt: skip
    assert machine_paths(transcript, "docs/x.md") == ["docs/x.md:3: wrote /" + "tmp/elsewhere/x.json"]
    assert machine_paths(transcript, "tests/x.py") == []  # tests use temporary folders


def test_no_file_holds_a_path_of_the_machine_it_was_made_on() -> None:
    found = [line for p in project_text_files()
             for line in machine_paths(p.read_text(encoding="utf-8"), p.relative_to(ROOT).as_posix())]  # fmt: skip
    assert not found, "these lines hold an absolute path of a machine (use a relative path):\n" + "\n".join(found)


# -- links -------------------------------------------------------------------------------------

_FENCE = re.compile(r"^```.*?^```", re.S | re.M)
_INLINE_CODE = re.compile(r"`[^`\n]*`")
_LINK = re.compile(r"\[[^\]\n]*\]\(([^)\s]+)\)")


def markdown_pages() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def links(page: Path) -> list[str]:
    """The link targets of a Markdown page, outside code blocks and inline code."""
    text = _FENCE.sub("", page.read_text(encoding="utf-8"))
    text = re.sub(r"\[(`[^`\n]*`)\]", lambda m: "[" + m.group(1).strip("`") + "]", text)  # [`x`](y) is a link
    text = _INLINE_CODE.sub("", text)
    return _LINK.findall(text)


def slug(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces as hyphens."""
    text = heading.strip().lower().replace("`", "")
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(page: Path) -> set[str]:
    text = _FENCE.sub("", page.read_text(encoding="utf-8"))
    return {slug(m.group(1)) for m in re.finditer(r"^#{1,6} (.+)$", text, re.M)}


def test_slug_matches_github():
    assert slug("`verify oracle check --json`") == "verify-oracle-check---json"
    assert slug("The certificate") == "the-certificate"


def test_links_are_found():
    """A guard: the link reader sees the README's link to docs/ and the index's pages."""
    assert "docs/README.md" in links(ROOT / "README.md")
    assert {"numbers.md", "records.md", "json-outputs.md", "cli.md", "oracle.md"} <= set(links(ROOT / "docs/README.md"))


@pytest.mark.parametrize("page", markdown_pages(), ids=lambda p: p.relative_to(ROOT).as_posix())
def test_relative_links_lead_to_files_that_exist(page: Path):
    broken = []
    for target in links(page):
        if re.match(r"[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
            continue
        path, _, anchor = target.partition("#")
        dest = (page.parent / path).resolve() if path else page
        if not dest.exists():
            broken.append(f"{target}: no such file")
        elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
            broken.append(f"{target}: no heading #{anchor} in {dest.relative_to(ROOT)}")
    assert not broken, f"{page.relative_to(ROOT)}: " + "; ".join(broken)


# -- the worked example of docs/records.md -------------------------------------------------------

EXAMPLE = "docs/examples/cases.json"


_BLOCK = re.compile(r"^```[^\n]*\n(.*?)^```", re.S | re.M)


def fenced_blocks(text: str) -> list[str]:
    """The contents of the fenced code blocks of a Markdown text, in order."""
    return [m.group(1) for m in _BLOCK.finditer(text)]


def block_after(text: str, line: str) -> str:
    """The content of the first fenced code block after the block whose content is ``line``."""
    at = text.index("```\n" + line + "\n```") + len(line) + 8
    return next(m.group(1) for m in _BLOCK.finditer(text, at))


def normalise(text: str) -> str:
    """The exact backend's label names the rational library installed (gmpy2, flint or python)."""
    return re.sub(r"exact \(rationals, [a-z0-9-]+\)", "exact (rationals, LIBRARY)", text)


def run_cli(argv: list[str], capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch) -> str:
    monkeypatch.chdir(ROOT)
    capsys.readouterr()
    code = main(argv)
    out = capsys.readouterr()
    assert code == 0, out.err
    return out.out


def test_records_example_shows_the_case_file():
    doc = (ROOT / "docs/records.md").read_text(encoding="utf-8")
    assert (ROOT / EXAMPLE).read_text(encoding="utf-8") in fenced_blocks(doc)


def test_records_example_shows_the_current_json_output(capsys, monkeypatch):
    doc = (ROOT / "docs/records.md").read_text(encoding="utf-8")
    shown = block_after(doc, f"$ verify solve {EXAMPLE} --json")
    real = run_cli(["solve", EXAMPLE, "--json"], capsys, monkeypatch)
    assert '"stop": "non_terminating"' in real and '"certificate"' in real  # the example shows both stops
    assert normalise(shown) == normalise(real), "docs/records.md: rerun the worked example and copy its output"


def test_records_example_shows_the_current_text_output(capsys, monkeypatch):
    doc = (ROOT / "docs/records.md").read_text(encoding="utf-8")
    marker = f"$ verify solve {EXAMPLE}"
    block = next(b for b in fenced_blocks(doc) if b.startswith(marker + "\n"))
    real = run_cli(["solve", EXAMPLE], capsys, monkeypatch)
    assert normalise(block[len(marker) + 1 :]) == normalise(real), "docs/records.md: rerun the worked example"


# -- every command output printed in docs/ (issue 34, item 7) ------------------------------------
#
# A transcript is a line ``$ verify ...`` in a fenced block of docs/*.md and the lines after it, up to
# the next ``$`` line or the end of the block: what the command prints. When the block holds the
# command alone, its output is the next fenced block (the JSON outputs). Each is run in this process
# (verify.cli.main), in a folder that holds the repository's golden/, docs/ and examples/ and the small
# files the pages describe in words (FILES), and compared with what the page shows:
#
# - what is compared: stdout; stderr when the command fails with exit code 2 (bad input); stderr then
#   stdout when the page shows progress lines (they go to stderr);
# - a line ``...`` (indented or not, with a trailing comma in JSON) stands for any number of lines
#   (a trimmed output), and ``...`` inside a line for any text in that line;
# - a JSON output may be trimmed: the page shows some keys of each object and some items of each
#   array, in order, each equal to the program's;
# - what depends on the machine is replaced on both sides (MACHINE): the rational library's name,
#   a wall time, and every number of ``verify bench`` (timings).

#: transcripts not run, and why (the command as printed on the page)
NOT_RUN = {
    "verify report --out /tmp/docrun/reports --profile dev --workers 1": "writes every report: about 95 s on 2 cores",
}

#: (pattern, replacement): what differs from machine to machine, replaced in the page and in the output
MACHINE = [
    (re.compile(r"rationals, [a-z0-9-]+\)"), "rationals, LIBRARY)"),  # gmpy2, flint or python, as installed
    (re.compile(r", exact, in [0-9.]+ s$", re.M), ", exact, in TIME s"),  # verify sweep's wall time
]
#: commands whose every number is a measurement of the machine (replaced by ``#``)
TIMINGS = ("bench",)


def _golden_results(edit: Callable[[list[dict]], list[dict]]) -> str:
    results = json.loads((ROOT / "golden/results.json").read_text(encoding="utf-8"))["results"]
    return json.dumps({"results": edit(results)}, indent=2)


def _wrong_results(results: list[dict]) -> list[dict]:
    """docs/oracle.md: three errors in paper-table1-eps-0.99 (2 impulses instead of 3, a wrong first
    component) and no result for paper-table1-eps-0.6."""
    out = []
    for r in results:
        if r["id"] == "paper-table1-eps-0.6":
            continue
        if r["id"] == "paper-table1-eps-0.99":
            r = {k: v for k, v in r.items() if k != "exit_velocity_decimal"}
            r.update(iterations=2, impact_sets=r["impact_sets"][:2], betas=r["betas"][:2])
            r["exit_velocity"] = ["0.5", *r["exit_velocity"][1:]]
        out.append(r)
    return out


def _case(**change: object) -> str:
    """A one-case file: the cradle of docs/examples/cases.json's second case, with ``change``."""
    case = json.loads((ROOT / EXAMPLE).read_text(encoding="utf-8"))["cases"][1]
    case.update(change)
    return json.dumps({"cases": [case]}, indent=2)


#: docs/numbers.md: a corner of half-angle 3/10
TAN = {
    "id": "c",
    "mass_matrix": [["1", "0"], ["0", "1"]],
    "normals": [["-tan(3/10)", "1"], ["-tan(3/10)", "-1"]],
    "restitution": ["1/2", "1/2"],
    "velocity": ["1", "0"],
}

#: the files that the pages describe in words, by name
FILES: dict[str, Callable[[], str]] = {
    "tan.json": lambda: json.dumps({"cases": [TAN]}),
    # docs/records.md, docs/numbers.md: a bare number, an unknown name, a matrix that is not positive
    # definite, dependent normals
    "bad1.json": lambda: _case(restitution=[0.5, "1/100"]),
    "bad2.json": lambda: _case(velocity=["1", "exp(1)", "0"]),
    "bad3.json": lambda: _case(mass_matrix=[["1", "2", "0"], ["2", "1", "0"], ["0", "0", "1"]]),
    "bad4.json": lambda: _case(normals=[["-1", "1", "0"], ["2", "-2", "0"]]),
    # docs/oracle.md
    "wrong_results.json": lambda: _golden_results(_wrong_results),
    "bad_results.json": lambda: _golden_results(lambda rs: [{**rs[0], "stop": "done"}, *rs[1:]]),
}


@dataclass(frozen=True)
class Transcript:
    page: str
    line: int
    command: str
    shown: str
    json: bool  # the output is the next fenced block

    def __str__(self) -> str:
        return f"{self.page}:{self.line}: $ {self.command}"


def transcripts() -> list[Transcript]:
    """Every ``$ verify ...`` of docs/*.md with the output the page shows for it."""
    found = []
    for page in sorted((ROOT / "docs").glob("*.md")):
        text = page.read_text(encoding="utf-8")
        blocks = list(_BLOCK.finditer(text))
        for k, block in enumerate(blocks):
            first = text.count("\n", 0, block.start(1)) + 1
            lines = block.group(1).splitlines()
            starts = [i for i, line in enumerate(lines) if line.startswith("$ ")]
            for i, j in zip(starts, [*starts[1:], len(lines)]):
                command = lines[i][2:]
                if not command.startswith("verify "):
                    continue
                shown, alone = lines[i + 1 : j], len(lines) == 1
                if alone and k + 1 < len(blocks):
                    shown = blocks[k + 1].group(1).splitlines()
                found.append(Transcript(page.name, first + i, command, "\n".join(shown), alone))
    return found


def _machine(text: str, argv: list[str]) -> str:
    text = "\n".join(line.rstrip() for line in text.splitlines())
    for pattern, replacement in MACHINE:
        text = pattern.sub(replacement, text)
    if argv[:1] and argv[0] in TIMINGS:  # the numbers, and so the widths of the columns
        text = re.sub(r" +", " ", re.sub(r"\d[\d,.]*", "#", text))
    return text


def _machine_json(value: Any, argv: list[str]) -> Any:
    """A JSON value with what depends on the machine replaced, as :func:`_machine` does for text."""
    if isinstance(value, dict):
        return {k: _machine_json(v, argv) for k, v in value.items()}
    if isinstance(value, list):
        return [_machine_json(v, argv) for v in value]
    if isinstance(value, str):
        return _machine(value, argv)
    if isinstance(value, (int, float)) and not isinstance(value, bool) and argv[0] in TIMINGS:
        return "#"
    return value


def _text_matches(shown: str, real: str) -> bool:
    """Whether ``real`` is what ``shown`` shows: a line ``...`` for any lines, ``...`` in a line for any text."""
    pattern = []
    for line in shown.splitlines():
        if line.strip().rstrip(",") == "...":
            pattern.append(r"(?:[^\n]*\n)*?")
        else:
            pattern.append(".*?".join(re.escape(part) for part in line.split("...")) + r"\n")
    return re.fullmatch("".join(pattern), real + "\n", re.S) is not None


def _json_within(shown: Any, real: Any) -> bool:
    """Whether the JSON ``shown`` is ``real`` with some keys and some array items left out."""
    if isinstance(shown, dict):
        return isinstance(real, dict) and all(k in real and _json_within(v, real[k]) for k, v in shown.items())
    if isinstance(shown, list):
        if not isinstance(real, list):
            return False
        items = iter(real)
        return all(any(_json_within(s, r) for r in items) for s in shown)
    return shown == real


def _shown_json(shown: str) -> Any:
    """The JSON a page shows, its ``...`` lines (trimmed parts) taken out."""
    kept = "\n".join(line for line in shown.splitlines() if line.strip().rstrip(",") != "...")
    return json.loads(re.sub(r",(\s*[}\]])", r"\1", kept))


@pytest.fixture(scope="module")
def doc_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder like the root of the repository (its golden/, docs/, examples/), with FILES."""
    folder = tmp_path_factory.mktemp("docs-run")
    for name in ("golden", "docs", "examples"):
        (folder / name).symlink_to(ROOT / name, target_is_directory=True)
    for name, content in FILES.items():
        (folder / name).write_text(content(), encoding="utf-8")
    return folder


def test_the_pages_have_transcripts_and_the_list_of_those_not_run_is_current():
    found = {t.command for t in transcripts()}
    assert len(found) > 30
    assert set(NOT_RUN) <= found, set(NOT_RUN) - found


@pytest.mark.parametrize("transcript", transcripts(), ids=str)
def test_every_command_output_in_the_docs_is_the_programs(
    transcript: Transcript,
    doc_folder: Path,
    capsys: pytest.CaptureFixture,
    monkeypatch: pytest.MonkeyPatch,
    tmp_path_factory: pytest.TempPathFactory,
):
    if transcript.command in NOT_RUN:
        pytest.skip(NOT_RUN[transcript.command])
    argv = shlex.split(transcript.command)[1:]
    if argv[0] == "bench":  # its numbers are the machine's (TIMINGS): one measurement for its transcripts
        bench_measured_once(monkeypatch, tmp_path_factory)
    monkeypatch.chdir(doc_folder)
    capsys.readouterr()
    try:
        code = main(argv)
    except SystemExit as exc:  # --help
        code = exc.code
    out, err = capsys.readouterr()
    if transcript.json:
        assert code in (0, 1), err
        real, shown_json = (_machine_json(x, argv) for x in (json.loads(out), _shown_json(transcript.shown)))
        assert _json_within(shown_json, real), f"{transcript}: rerun it and copy its output"
        return
    shown = _machine(transcript.shown, argv)
    assert code != 2 or out == "", f"{transcript}: bad input, yet something on stdout: {out}"
    seen = [err] if code == 2 else [out, err + out]
    assert any(_text_matches(shown, _machine(s, argv)) for s in seen), (
        f"{transcript}: the page shows\n{transcript.shown}\n--- the program prints (exit code {code})\n"
        + (err if code == 2 else out)
    )
