"""Errors a user can cause and fix; the CLI prints them as one paragraph, without a traceback."""


class WecCosimError(Exception):
    """Base class of user-facing errors: the message says what is wrong, where, and what to do."""


class ScenarioError(WecCosimError):
    """A scenario file is invalid (the message names the file and the key path)."""


class MasterError(WecCosimError):
    """The co-simulation could not continue (the message names the component, time and cause)."""
