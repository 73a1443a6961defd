"""Command-line flags made from the build's stage configs (`sg3d.ingest.config`): a field's flag is
its name with dashes, its help the field's help with the default it stands for, so `--help` shows
the default a build uses. The flags given reach the command as one dict (only those given)."""
from __future__ import annotations

import functools
from typing import Any, Callable, Optional

import click

from sg3d.ingest.config import help_of

# click types where a field's own type says too little (its range)
_TYPES: dict[str, Any] = {"detect_fraction": click.FloatRange(0.0, 1.0, min_open=True)}


def flag_of(name: str) -> str:
    return "--" + name.replace("_", "-")


def config_options(config: type, names: tuple[str, ...], dest: str,
                   extra_help: Optional[dict[str, str]] = None) -> Callable[[Callable], Callable]:
    """Add a flag per field `names` of `config` to a click command; the command receives the
    values given as `dest` (a dict: field name -> value, only the flags given)."""
    def decorate(fn: Callable) -> Callable:
        @functools.wraps(fn)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            kwargs[dest] = {k: v for k in names if (v := kwargs.pop(k)) is not None}
            return fn(*args, **kwargs)

        for name in reversed(names):
            default = getattr(config(), name)
            kind = _TYPES.get(name, type(default) if isinstance(default, (int, float)) else float)
            text = help_of(config, name) + ((" " + extra_help[name]) if extra_help and name in extra_help else "")
            wrapper = click.option(flag_of(name), name, type=kind, default=None, help=text)(wrapper)
        return wrapper
    return decorate
