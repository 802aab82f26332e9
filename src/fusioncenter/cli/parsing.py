"""The command line's arguments: the parser of its subcommands and options
(:func:`build_parser`, with the environment and the exit codes in ``EPILOG``) and the
``--set KEY=VALUE`` overrides (:func:`parse_overrides`)."""

from __future__ import annotations

import argparse
from pathlib import Path

from fusioncenter.profile import ENV_VAR as PROFILE_ENV
from fusioncenter.profile import PROFILES

__all__ = ["CACHE_ENV", "EXECUTOR_ENV", "DESCRIPTION", "EPILOG", "build_parser",
           "parse_overrides"]

CACHE_ENV = "FUSIONCENTER_COMPUTE_CACHE"
EXECUTOR_ENV = "FUSIONCENTER_EXECUTOR"
#: The first line of ``fusioncenter --help``.
DESCRIPTION = "Command line: regenerate any figure or table without the book."

EPILOG = f"""environment:
  {PROFILE_ENV}      default profile (fast or paper)
  {EXECUTOR_ENV}     default executor (auto, serial, processes[:N], dask:...)
  {CACHE_ENV}  a folder: computed entries are kept there and read back
      (npz files keyed by id, profile, seed, overrides and the library's version and
      source fingerprint, with an integrity check; a stale or altered file is computed
      again); unset: every run computes

exit codes: 0 ok, 1 a claim failed, 2 bad usage (bad id, option, --set value or bound,
  a run too large for the memory), 3 runtime or I/O error (output, cache, workers,
  scheduler, memory exhausted), 4 internal error, 130 interrupted, 143 terminated
"""


def build_parser() -> argparse.ArgumentParser:
    """The parser of the command line's five subcommands and their options.

    Returns
    -------
    argparse.ArgumentParser
        ``fusioncenter`` with the subcommands ``list``, ``params``, ``compute``, ``plot`` and
        ``verify`` (the parsed ``cmd``), each with ``EPILOG`` (the environment variables
        and the exit codes) under its help.
    """
    p = argparse.ArgumentParser(prog="fusioncenter", description=DESCRIPTION,
                                epilog=EPILOG,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)

    def add(name, **kw):
        return sub.add_parser(name, epilog=EPILOG,
                              formatter_class=argparse.RawDescriptionHelpFormatter, **kw)

    sp = add("list", help="list every figure and table with its status")
    sp.add_argument("--json", action="store_true", help="machine-readable output")

    sp = add("params", help="list an entry's parameters that --set may override")
    sp.add_argument("id", help="registry id, e.g. zheng2014-table1")

    def common(sp):
        sp.add_argument("id", help="registry id, e.g. dey2009-fig1")
        sp.add_argument("--profile", choices=PROFILES, default=None,
                        help=f"default: ${PROFILE_ENV}, else fast")
        sp.add_argument("--seed", type=int, default=None, help="non-negative integer")
        sp.add_argument("--executor", default=None, metavar="SPEC",
                        help="auto, serial, processes[:N], dask:local or dask:ADDRESS "
                        f"(default: ${EXECUTOR_ENV}, else auto: serial, or a pool of the "
                        "cores for a Monte Carlo run long enough to repay its ~5 s start-up)")
        sp.add_argument("--set", dest="overrides", action="append", default=[],
                        metavar="KEY=VALUE", help="override a parameter (see `params ID`); "
                        "each key at most once")

    sp = add("compute", help="compute an entry's data")
    common(sp)
    out = sp.add_mutually_exclusive_group(required=True)
    out.add_argument("--json", action="store_true", help="write JSON to stdout")
    out.add_argument("--csv", metavar="FILE", type=Path,
                     help="write long-format CSV to FILE (`-`: standard output)")

    sp = add("plot", help="compute and plot an entry into a directory")
    common(sp)
    sp.add_argument("-o", "--outdir", type=Path, required=True)
    sp.add_argument("--format", choices=["png", "pdf", "svg"], default="png")

    sp = add("verify", help="compute an entry and check the paper's claims on it")
    common(sp)
    return p


def parse_overrides(pairs: list[str]) -> dict:
    """The ``--set KEY=VALUE`` pairs of the command line as a dict (values still text).

    Parameters
    ----------
    pairs : list of str
        The values given to ``--set``, in order.

    Returns
    -------
    dict
        Key (blanks around it removed) to value text, in the order given; the entry's
        :class:`~fusioncenter.context.parameters.Parameter` parses the values.

    Raises
    ------
    ValueError
        If an item has no ``=`` or an empty key, or a key is given twice.
    """
    out = {}
    for item in pairs:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise ValueError(f"--set expects KEY=VALUE, got {item!r}")
        key = key.strip()
        if key in out:
            raise ValueError(f"--set {key} given twice ({out[key]!r} and {value!r}); give each "
                             "key once")
        out[key] = value
    return out
