"""The ``vhfit`` command line: fit, demo, simulate, export, models.

Run ``vhfit --help`` or ``python -m vhfit --help``; docs/cli.md documents every
command, flag, file and exit code. Exit codes:

* 0 — success;
* 1 — the fit failed, or was interrupted (outputs are still written, marked
  "interrupted", and the message says how to ``--resume``);
* 2 — bad input (a file, a flag, an option): one line naming the file and the fix.

Errors are one line on stderr (``vhfit: error: ...``), never a traceback; ``--debug``
shows the traceback instead.

The package has one private module per command (``_fit`` for ``fit`` and ``demo``,
``_simulate``, ``_export``, ``_models``), the parser (``_parser``), the entry point
(``_main``), plug-in loading (``_plugins``) and what the commands share (``_common``).
"""

from vhfit.cli._common import (
    EXIT_FAILED,
    EXIT_OK,
    EXIT_USAGE,
    FitFailed,
    Progress,
    UsageError,
)
from vhfit.cli._main import main, program
from vhfit.cli._parser import build_parser
from vhfit.cli._plugins import PLUGIN_GROUP, load_plugins


def __getattr__(name: str):
    # the card table lives with the fitting code (numpy, scipy): loaded when first asked
    if name == "CARD_FILES":
        from vhfit.cli._cards import CARD_FILES

        return CARD_FILES
    raise AttributeError(f"module 'vhfit.cli' has no attribute {name!r}")


__all__ = [
    "main",
    "program",
    "build_parser",
    "load_plugins",
    "PLUGIN_GROUP",
    "EXIT_OK",
    "EXIT_FAILED",
    "EXIT_USAGE",
    "UsageError",
    "FitFailed",
    "Progress",
    "CARD_FILES",
]
