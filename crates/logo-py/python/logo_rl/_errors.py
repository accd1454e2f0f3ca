"""The kinds of :class:`logo_rl.LogoError`: each is also the exception Python code would
raise for the same mistake, so ``except FileNotFoundError`` and ``except LogoError`` both
catch a config file that is not there."""

from ._logo_rl import LogoError


class LogoFileNotFoundError(LogoError, FileNotFoundError):
    """A file logo-rl was given (a config, a checkpoint, demonstrations) is not there."""


class LogoTypeError(LogoError, TypeError):
    """A config key given a value of the wrong type."""


class LogoValueError(LogoError, ValueError):
    """A value logo-rl refuses: an unknown or missing key, a number out of its range, an
    unknown env id, a file that is not what it should be."""
