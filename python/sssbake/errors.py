"""The exceptions sssbake raises: one class per kind of error the library
reports, each carrying where the problem is when that is known."""

from __future__ import annotations


class Error(Exception):
    """Something sssbake could not do; `kind` names which kind of error it
    is (`input`, `setting`, `output`, `cancelled`), `message` says what is
    wrong, and `file`, `object` and `field` say where, when known."""

    kind = "error"

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        object: str | None = None,
        field: str | None = None,
    ) -> None:
        super().__init__(message)
        self.message = message
        self.file = file
        self.object = object
        self.field = field


class InputError(Error):
    """A scene, material, image or manifest that cannot be used as it is."""

    kind = "input"


class SettingError(Error):
    """An option out of its range, or a request over its limits."""

    kind = "setting"


class OutputError(Error):
    """An output that cannot be written (nothing was half-written)."""

    kind = "output"


class Cancelled(Error):
    """The work stopped because it was asked to (a cancel event or Ctrl-C)."""

    kind = "cancelled"
