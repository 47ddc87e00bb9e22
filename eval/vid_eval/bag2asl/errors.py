"""Typed errors of the converter; the CLI turns each into one line on stderr and exit code 1."""


class Bag2AslError(Exception):
    """Base class: the message is the complete one-line explanation."""


class UsageError(Bag2AslError):
    """A command-line value that cannot be used (exit 2, as argparse's own usage errors)."""


class ConfigError(Bag2AslError):
    """Bad topic map, preset or command-line value (message names file and key)."""


class MissingTopicError(Bag2AslError):
    """A required topic is not in the bag (message lists the topics the bag has)."""


class UnknownTypeError(Bag2AslError):
    """A message type has no definition in the bag nor in the fallback store, or is unsupported."""


class CorruptBagError(Bag2AslError):
    """The bag cannot be read: truncated, unindexed, bad chunk or undecodable message."""


class DiskFullError(Bag2AslError):
    """Writing an output file failed because the disk is full (ENOSPC) or another OS error."""
