"""A log of what a bake changed in the artist's scene, each change with the step that
undoes it, so a bake that fails at any stage puts everything back as it was."""


class Changes:
    """Undo steps in the order the changes were made; `rollback()` runs them newest first."""

    def __init__(self):
        self._undo = []

    def record(self, undo):
        """Remembers `undo`, a callable that reverts the change just made."""
        self._undo.append(undo)

    def rollback(self):
        """Reverts every recorded change, newest first. A step that fails does not stop the
        others; the failures come back as messages (empty when everything was put back)."""
        failures = []
        while self._undo:
            undo = self._undo.pop()
            try:
                undo()
            except Exception as error:  # noqa: BLE001 (every other step must still run)
                failures.append(str(error))
        return failures

    def forget(self):
        """Keeps the changes: the bake succeeded."""
        self._undo.clear()
