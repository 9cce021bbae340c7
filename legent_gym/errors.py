"""Errors shared across the command line's front ends."""


class UserError(Exception):
    """A problem with the user's input (a bad file, a bad argument): the ``legent-gym``
    command prints its message on one line, without a traceback, and exits 2."""
