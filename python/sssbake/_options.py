"""Bake options as the library reads them: the batch manifest's `BakeOptions` as JSON."""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from typing import Any


def options_json(options: Mapping[str, Any]) -> str:
    """`options` as JSON, paths as strings and collections as lists."""

    def plain(value: Any) -> Any:
        if isinstance(value, os.PathLike):
            return os.fspath(value)
        if isinstance(value, (list, tuple, set, frozenset)):
            return [plain(v) for v in value]
        return value

    return json.dumps({key: plain(value) for key, value in options.items()})
