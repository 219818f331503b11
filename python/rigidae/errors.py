"""The exceptions rigidae raises.

InputError  (a ValueError): a scene, study or option that cannot be used as
            given. The message is the CLI's (``FILE:LINE:COL: error: ...`` for
            files, ``scene['body']['mas']: error: ...`` for dicts, ``option
            --rtol: ...`` for options) and says what would be valid.
SolverError (a RuntimeError): the integrator could not continue. ``.run``
            holds the records up to the failure (``.run.steps``, ``.run.grid``,
            ``.run.summary``).
Interrupted (a KeyboardInterrupt): Ctrl-C stopped a run after its current
            step; ``.run`` holds the records so far (for solve).
"""
import re

_POSITION = re.compile(r"^(?P<file>.*?):(?P<line>\d+):(?P<column>\d+): error: (?P<detail>.*)$", re.S)
_SUGGESTION = re.compile(r"did you mean ['\"](?P<word>[^'\"]*)['\"]\?")
_OPTION = re.compile(r"^option (?P<option>--[a-z-]+)")


class InputError(ValueError):
    """Bad input: a scene, study or option that cannot be used as given.

    Attributes (None when the message does not have them):
      message     the full message, as the CLI prints it
      file, line, column   where in the scene file (for file scenes)
      key         the key path in a scene dict, e.g. ('body', 'mas')
      detail      the message without its position
      suggestion  the valid word a "did you mean" names
      option      the option, as the keyword argument's name (e.g. 'rtol')
    """

    def __init__(self, message, key=None):
        super().__init__(message)
        self.message = message
        self.key = key
        self.file = self.line = self.column = self.option = None
        self.detail = message
        m = _POSITION.match(message)
        if m:
            self.file = m["file"]
            self.line, self.column = int(m["line"]), int(m["column"])
            self.detail = m["detail"]
        m = _SUGGESTION.search(message)
        self.suggestion = m["word"] if m else None
        m = _OPTION.match(message)
        if m:
            self.option = m["option"][2:].replace("-", "_")


class SolverError(RuntimeError):
    """The integrator could not continue; ``.run`` keeps the records up to the failure."""

    def __init__(self, message, run=None):
        super().__init__(message)
        self.message = message
        self.run = run


class Interrupted(KeyboardInterrupt):
    """Ctrl-C stopped the run between steps; ``.run`` keeps the records so far."""

    def __init__(self, message="interrupted", run=None):
        super().__init__(message)
        self.message = message
        self.run = run
