"""gmotion from Python: run a G-code program through the motion pipeline and get its trace as numpy.

    import gmotion
    r = gmotion.run("programs/square.nc", profile="scurve1", tau=0.1)
    r.trace["x_enc"]          # numpy array, the same values as the CSV trace's x_enc column
    r.summary["cycle_time_s"] # the --summary-json dict

    gmotion.check("part.nc")  # raises gmotion.ProgramError at the first error
    gmotion.moves("part.nc")  # the canonical moves, as `gmotion moves` prints them
    d = gmotion.design("blackman", tau=0.164, period=0.004)   # `gmotion design`: d.taps (numpy)
    gmotion.response("blackman", 0.164, 0.004)                # `gmotion analyze response`
    gmotion.radius_error("linear", 0.041, 0.001, radius=150)  # `gmotion analyze radius-error`

The keyword options of run() are the `gmotion run` flags that change the run (docs/cli.md), with
dashes as underscores: the one table of run settings (src/setup/run_settings.cpp) names them for
the CLI, golden cases, sweeps and Python alike; `gmotion.options("run")` lists them (profile, tau,
period, blu, axes, no_servo, block_delete, tool_table, override, rapid_override, override_file,
decimate, tolerance, tolerance_on, check_tolerance, max_time, dialect, ...). servo (False =
no_servo) and schedule (= override_file) are accepted too. The GIL is released while a program
runs, so runs in threads proceed in parallel.
"""

import json
import os

from . import _core

__all__ = ["run", "check", "moves", "design", "response", "radius_error", "options", "RunResult",
           "CheckResult", "Design", "ProgramError", "InputError", "__version__"]

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


def options(what="run"):
    """The keyword options run(), check() or moves() take (what = "run", "check", "moves"): the
    run settings' flag names with '_' for '-' (one table for the CLI, golden cases, sweeps and
    Python)."""
    return list(_core.options(what))


def _paths(options):
    """`options` with path-like values (pathlib.Path) made strings."""
    return {k: (os.fspath(v) if isinstance(v, os.PathLike) else v) for k, v in options.items()}


def check(program, machine=None, **options):
    """Checks `program` (a path) as `gmotion check` does, on `machine` (a machine file path;
    None = the built-in machine). Options (options("check")): block_delete, max_iterations,
    subroutine_path ("DIR[:DIR...]"), dialect ("linuxcnc", "fanuc", "haas", "grbl", "mach3"), parameter_file,
    no_parameter_file, axes, tool_table, user_mcode_dir.
    Returns a CheckResult; raises ProgramError at the first error."""
    d = _core.check(os.fspath(program), "" if machine is None else os.fspath(machine),
                    _paths(options))
    err = _first_error(d["diagnostics"])
    if err is not None:
        raise err
    return CheckResult(d)


def run(program, machine=None, **options):
    """Runs `program` (a path) on `machine` (a machine file path; None = the built-in machine)
    with the `run` flags as keyword options. Returns a RunResult; raises ProgramError when the
    program has an error (nothing runs then) and InputError for a bad machine, option or a stop
    rule."""
    d = _core.run(os.fspath(program), "" if machine is None else os.fspath(machine),
                  _paths(options))
    if "diagnostics" in d:
        raise _first_error(d["diagnostics"])
    return RunResult(d)


def moves(program, machine=None, axes="", messages=False, **options):
    """The canonical moves of `program` as `gmotion moves` prints them: a list of dicts with the
    same keys ("line", "kind" rapid|line|arc|rigid_tap|probe|dwell, "end" [x, y, z] mm, "feed"
    mm/min, "axes" {letter: value} past XYZ, "center"/"dir"/"turns"/"plane" for arcs, "seconds"
    for dwells;
    with messages=True also "message" records). Options as check() (axes is its own argument).
    Raises InputError if the program has an error."""
    return _core.moves(os.fspath(program), "" if machine is None else os.fspath(machine), axes,
                       messages, _paths(options))


class _Record:
    """Attribute access over a result dict (the keys of the command's --json output)."""

    def __init__(self, d):
        self.__dict__.update(d)

    def __repr__(self):
        keys = ", ".join(k for k in self.__dict__ if not k.startswith("_"))
        return f"{type(self).__name__}({keys})"


class Design(_Record):
    """`gmotion design`: .taps (real, DC gain 1) and .taps_int (applied) as numpy arrays, .b_s,
    .N, .tau (after the procedure), .cutoff, .peak_accel (m/s^2), .peak_force (N), .peak_power
    (W), .v_ok/.f_ok/.p_ok/.ok, .attempts (one dict per tau tried)."""

    def response(self, points=201):
        """The amplitude response of these taps: `response()` for the design's profile and tau."""
        return response(self.profile, self.tau, self.period, points)


def design(profile="blackman", tau=0.164, period=0.004, v_max=1.0, mass=500.0, damping=500.0,
           f_max=4000.0, p_max=500.0, v_step=0.1, max_attempts=2000):
    """The paper's Fig. 9 design procedure, as `gmotion design --json` (same defaults: the
    paper's section 6 example). Limits in m/s, kg, kg/s, N, W."""
    return Design(_core.design(profile, tau, period, v_max, mass, damping, f_max, p_max, v_step,
                               max_attempts))


def response(profile="blackman", tau=0.164, period=0.004, points=201):
    """`gmotion analyze response`: a _Record with .f_norm (0..1 of Nyquist), .f_hz, .amplitude
    (real taps) and .amplitude_int (applied integer taps) as numpy arrays, and the taps."""
    return _Record(_core.response(profile, tau, period, points))


def radius_error(profile="linear", tau=0.041, period=0.001, radius=150.0,
                 feeds=(30000, 25000, 20000, 15000, 10000, 8000, 6000, 4000, 2000, 1000, 600,
                        400, 200)):
    """`gmotion analyze radius-error`: radius loss of a circle of `radius` mm per feed (mm/min),
    in µm: .sampled_um (the sampled filter, any profile), .continuous_linear_um (Eq. 18) and
    .approx_linear_um (Eq. 19) for reference, .feed_mm_min, all numpy arrays."""
    return _Record(_core.radius_error(profile, tau, period, radius, [float(f) for f in feeds]))
