"""The files of verify: JSON read with one loader, files written whole.

:func:`load_json` reads a case or result file (size limit, numbers kept as strings so that the
field holding a bare JSON number can be named). :func:`write_atomic` and
:func:`write_all_atomic` write each file to a temporary name beside it, then rename it into
place: a write that fails or is interrupted leaves neither a partial file nor a temporary one of
its own, and the file that was there before stays as it was.

>>> import os, tempfile
>>> folder = tempfile.mkdtemp()
>>> write_atomic(os.path.join(folder, "sub", "a.txt"), "one\\n")
>>> write_all_atomic({os.path.join(folder, "b.bin"): b"\\x00", os.path.join(folder, "c.txt"): "two\\n"})
>>> from pathlib import Path
>>> sorted(os.listdir(folder)), Path(folder, "sub", "a.txt").read_text()
(['b.bin', 'c.txt', 'sub'], 'one\\n')
>>> import shutil; shutil.rmtree(folder)
"""

from __future__ import annotations

import os
import sys
from collections.abc import Mapping
from typing import Any

from verify.errors import InvalidInput

#: the suffix of a file's temporary name while it is written
TMP_SUFFIX = ".tmp"

Data = str | bytes
FilePath = str | os.PathLike[str]

#: the file name that means standard input (a case or result file) or standard output (``--out``, ``--junit``)
STDIO = "-"
_STDIN: list[tuple[Any, str]] = []  # (the stream, its text): standard input is read once


def display_name(path: str) -> str:
    """The name of ``path`` in messages: ``stdin`` for ``-``.

    >>> display_name("-"), display_name("cases.json")
    ('stdin', 'cases.json')
    """
    return "stdin" if path == STDIO else path


def read_text(path: str, max_bytes: int | None = None) -> str:
    """The UTF-8 text of the file ``path``, or of standard input for ``-`` (read once: a second call gives the
    same text), at most ``max_bytes`` (default :data:`MAX_FILE_BYTES`); each way it can fail is one
    :class:`~verify.errors.InvalidInput` line naming the file.

    >>> read_text("no/such/file.json")
    Traceback (most recent call last):
    ...
    verify.errors.InvalidInput: no/such/file.json: cannot read (No such file or directory)
    """
    limit = MAX_FILE_BYTES if max_bytes is None else max_bytes
    try:
        if path == STDIO:
            if not _STDIN or _STDIN[0][0] is not sys.stdin:
                stream = getattr(sys.stdin, "buffer", None)  # the bytes, decoded as UTF-8 whatever the locale
                data = stream.read(limit + 1) if stream is not None else sys.stdin.read(limit + 1).encode("utf-8")
                if len(data) > limit:
                    raise InvalidInput(f"stdin: larger than {limit} bytes")
                _STDIN[:] = [(sys.stdin, data.decode("utf-8"))]
            text = _STDIN[0][1]
        else:
            if os.path.getsize(path) > limit:
                raise InvalidInput(f"{path}: larger than {limit} bytes")
            with open(path, encoding="utf-8") as fh:
                text = fh.read()
    except OSError as exc:
        raise InvalidInput(f"{display_name(path)}: cannot read ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise InvalidInput(f"{display_name(path)}: not UTF-8 text") from None
    if len(text) > limit:
        raise InvalidInput(f"{display_name(path)}: larger than {limit} bytes")
    return text


def write_atomic(path: FilePath, data: Data) -> None:
    """Write ``data`` (text as UTF-8 with ``\\n`` line ends, or bytes) to ``path``, creating its folder:
    whole to ``path + ".tmp"``, then renamed into place."""
    write_all_atomic({path: data})


def write_all_atomic(files: Mapping[FilePath, Data]) -> None:
    """Write every file of ``files`` (path -> data) as :func:`write_atomic` does, all to their
    temporary names first and renamed only once every one is written: a failure leaves every
    file as it was and removes the temporary files written so far."""
    written: list[str] = []
    try:
        for path, data in files.items():
            tmp = os.fspath(path) + TMP_SUFFIX
            os.makedirs(os.path.dirname(os.path.abspath(tmp)), exist_ok=True)
            if isinstance(data, bytes):
                with open(tmp, "wb") as fh:
                    written.append(tmp)
                    fh.write(data)
            else:
                with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
                    written.append(tmp)
                    fh.write(data)
    except BaseException:  # a failed or interrupted write leaves no temporary file of its own
        for tmp in written:
            if os.path.isfile(tmp):
                os.remove(tmp)
        raise
    for path in files:
        os.replace(os.fspath(path) + TMP_SUFFIX, path)


# -- reading ----------------------------------------------------------------------------------

#: the largest JSON file (or text) read: a case or result file larger than this is refused
MAX_FILE_BYTES = 64 * 1024 * 1024


class BareJSONNumber:
    """A JSON number with a fraction or exponent (``0.5``): kept as text so that the field that
    holds it can be named in the error; numbers must be strings (contracts)."""

    __slots__ = ("json_number_text",)

    def __init__(self, text: str):
        self.json_number_text = text


class BareJSONConstant:
    """``NaN``, ``Infinity`` or ``-Infinity`` written bare in a JSON file (Python's ``json.dump``
    writes them): kept as text, like :class:`BareJSONNumber`, so that the field that holds it can
    be named (:func:`load_json` with ``constants=True``)."""

    __slots__ = ("json_constant_text",)

    def __init__(self, text: str):
        self.json_constant_text = text


def _constant_refuser(what: str) -> Any:
    def refuse(text: str) -> Any:
        raise InvalidInput(f"{what}: {text} is not a number (a bare JSON {text}; numbers are strings)")

    return refuse


def load_json(
    what: str,
    *,
    path: FilePath | None = None,
    text: str | None = None,
    max_bytes: int | None = None,
    constants: bool = False,
) -> Any:
    """The JSON value of the file ``path``, or of ``text`` (give one), read with the size limit
    ``max_bytes`` (default :data:`MAX_FILE_BYTES`); numbers with a fraction or an exponent
    come back as :class:`BareJSONNumber`. A bare ``NaN``, ``Infinity`` or ``-Infinity`` comes
    back as :class:`BareJSONConstant` with ``constants=True`` (the caller names its field), and
    is refused otherwise. Every error is an :class:`~verify.errors.InvalidInput`; those about the
    file as a whole (unreadable, too large, not JSON, nested too deeply, a refused ``NaN``) start
    with ``what``, the file's name.

    >>> load_json("a.json", text='{"cases": [1, "1/2"]}')
    {'cases': [1, '1/2']}
    >>> load_json("a.json", text="[NaN]")
    Traceback (most recent call last):
    ...
    verify.errors.InvalidInput: a.json: NaN is not a number (a bare JSON NaN; numbers are strings)
    >>> load_json("a.json", text="[NaN]", constants=True)[0].json_constant_text
    'NaN'
    """
    import json

    if (path is None) == (text is None):
        raise ValueError("load_json: give exactly one of path and text")
    limit = MAX_FILE_BYTES if max_bytes is None else max_bytes
    on_constant = BareJSONConstant if constants else _constant_refuser(what)
    try:
        if path is not None:
            try:
                size = os.path.getsize(path)
            except OSError as exc:
                raise InvalidInput(f"{what}: cannot read ({exc.strerror})") from None
            if size > limit:
                raise InvalidInput(f"{what}: larger than {limit} bytes")
            with open(path, encoding="utf-8") as fh:
                return json.load(fh, parse_float=BareJSONNumber, parse_constant=on_constant)
        assert text is not None
        if len(text) > limit:
            raise InvalidInput(f"{what}: larger than {limit} bytes")
        return json.loads(text, parse_float=BareJSONNumber, parse_constant=on_constant)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InvalidInput(f"{what}: not valid JSON ({exc})") from None
    except RecursionError:
        raise InvalidInput(f"{what}: nested too deeply") from None
