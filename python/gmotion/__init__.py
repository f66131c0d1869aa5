"""gmotion from Python: run a G-code program through the motion pipeline and get its trace as numpy.

    import gmotion
    r = gmotion.run("programs/square.nc", profile="scurve1", tau=0.1)
    r.trace["x_enc"]          # numpy array, the same values as the CSV trace's x_enc column
    r.summary["cycle_time_s"] # the --summary-json dict

    gmotion.check("part.nc")  # raises gmotion.ProgramError at the first error

The keyword options of run() are the `gmotion run` flags (docs/cli.md) with dashes as
underscores: profile, tau, period, blu, servo (False = --no-servo), block_delete, tool_table,
override, rapid_override, schedule (an override-schedule file), decimate, tolerance, max_time,
max_iterations. The GIL is released while a program runs, so runs in threads proceed in parallel.
"""

import json
import os

from . import _core

__all__ = ["run", "check", "RunResult", "CheckResult", "ProgramError", "InputError", "__version__"]

__version__ = _core.version

#: A bad machine file, flag value, override schedule, or a run stopped by a stop rule.
InputError = _core.InputError


class ProgramError(ValueError):
    """The program has an error: where (file, line, column), its catalogue code and message.

    str() is the located diagnostic with the caret, as `gmotion check` prints it."""

    def __init__(self, diagnostic, diagnostics=()):
        super().__init__(diagnostic["text"].rstrip("\n"))
        self.file = diagnostic["file"]
        self.line = diagnostic["line"]
        self.column = diagnostic["column"]
        self.code = diagnostic["code"]
        self.message = diagnostic["message"]
        #: every diagnostic of the program (errors and warnings), as dicts
        self.diagnostics = list(diagnostics)


def _first_error(diagnostics):
    for d in diagnostics:
        if d["severity"] == "error":
            return ProgramError(d, diagnostics)
    return None


class CheckResult:
    """What `gmotion check` reports: blocks, moves, path length, time at programmed feed, warnings."""

    def __init__(self, d):
        self.blocks = d["blocks"]
        self.moves = d["moves"]
        self.path_length_mm = d["path_length_mm"]
        self.time_at_feed_s = d["time_at_feed_s"]
        self.diagnostics = d["diagnostics"]

    def __repr__(self):
        return (f"CheckResult(blocks={self.blocks}, moves={self.moves}, "
                f"path_length_mm={self.path_length_mm:.3f}, time_at_feed_s={self.time_at_feed_s:.3f})")


class RunResult:
    """A completed run: .trace maps each trace column to a numpy array (every sample unless
    decimate was given), .summary is the --summary-json dict, .header the trace header lines."""

    def __init__(self, d):
        self.columns = list(d["columns"])
        self.trace = d["trace"]
        self.summary = json.loads(d["summary_json"])
        self.header = list(d["header"])
        self.tolerance_text = d["tolerance"]
        #: False when the program ended but the axes did not settle (see unsettled_reason)
        self.finished = d["finished"]
        self.unsettled_reason = d["unsettled_reason"]

    def to_pandas(self):
        """The trace as a pandas DataFrame (needs pandas)."""
        import pandas  # optional dependency
        return pandas.DataFrame({c: self.trace[c] for c in self.columns})

    def __repr__(self):
        n = len(self.trace[self.columns[0]]) if self.columns else 0
        return f"RunResult({n} rows x {len(self.columns)} columns, finished={self.finished})"


def check(program, block_delete=False, max_iterations=None):
    """Checks `program` (a path) as `gmotion check` does. Returns a CheckResult; raises
    ProgramError at the first error."""
    kw = {"block_delete": block_delete}
    if max_iterations is not None:
        kw["max_iterations"] = max_iterations
    d = _core.check(os.fspath(program), **kw)
    err = _first_error(d["diagnostics"])
    if err is not None:
        raise err
    return CheckResult(d)


def run(program, machine=None, **options):
    """Runs `program` (a path) on `machine` (a machine file path; None = the built-in machine)
    with the `run` flags as keyword options. Returns a RunResult; raises ProgramError when the
    program has an error (nothing runs then) and InputError for a bad machine, option or a stop
    rule."""
    if "schedule" in options and options["schedule"] is not None:
        options["schedule"] = os.fspath(options["schedule"])
    if "tool_table" in options and options["tool_table"] is not None:
        options["tool_table"] = os.fspath(options["tool_table"])
    d = _core.run(os.fspath(program), "" if machine is None else os.fspath(machine), options)
    if "diagnostics" in d:
        raise _first_error(d["diagnostics"])
    return RunResult(d)
