"""What the command-line suites share about output folders: what a run left in one."""

from __future__ import annotations

from pathlib import Path


def listing(folder: Path) -> dict[str, bytes] | None:
    """Every file below ``folder`` with its bytes (None: no folder)."""
    if not folder.exists():
        return None
    return {str(p.relative_to(folder)): p.read_bytes() if p.is_file() else b"<dir>"
            for p in sorted(folder.rglob("*"))}
