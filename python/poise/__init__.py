"""Poise from Python: run studies, get their samples as NumPy arrays, evaluate a study's
outputs at inputs you choose, check error budgets, CAD mass properties and measured data.

Built with Poise (CMake target ``_poise``); import with ``PYTHONPATH=build/python``::

    import poise
    r = poise.run("studies/los_seeker_wang2011.toml", samples=4096, seed=1, threads=2,
                  overrides={"yaw.bearing_span": "70 mm"})
    r.outputs["los_max_arcsec"]        # numpy float64 array, one value per sample
    r.summary["answer"]                # the run's answer, as summary.json holds it

    s = poise.Study("studies/los_seeker_wang2011.toml")
    y = s.evaluate({"pitch_perpendicularity_arcsec": x1})   # other inputs at nominal

Every number is the command line's: ``poise.run`` writes the folder ``poise run`` writes
(``out=None``: a temporary one, removed) and reads its samples.csv back, so its arrays equal
that file value for value. Invalid input raises :class:`InputError` (a ``ValueError``) with
``file``, ``line`` and ``key``; any other failure :class:`Error`. Poise computes with the GIL
released; Ctrl-C during a run stops it as on the command line (``KeyboardInterrupt``).
"""
import difflib
import os
import re
import typing
import warnings

import numpy as np

from . import _poise

__all__ = ["run", "Study", "Result", "Sample", "Optimization", "SineFit", "RecordDiagnosis", "validate", "replay",
           "optimize", "fit", "diagnose_record", "error_mechanisms", "sensitivity", "balance", "budget", "mass_properties", "diagnose", "Error", "InputError", "RefusedValue", "PoiseWarning",
           "version"]

version = _poise.version


class Error(RuntimeError):
    """A failure of Poise that is not a refused input (a run that could not write, ...)."""


class RefusedValue(typing.NamedTuple):
    """One refused value of an input: where it is (``file``, ``line``: None where not known),
    its ``key`` and ``value``, what was ``expected``, and the whole ``message``."""
    message: str
    file: typing.Optional[str] = None
    line: typing.Optional[int] = None
    key: typing.Optional[str] = None
    value: typing.Optional[str] = None
    expected: typing.Optional[str] = None


class InputError(ValueError, Error):
    """Refused input: ``file``, ``line`` and ``key`` say where (None where not known): those of
    the first refused value that has a line. ``errors`` lists every refused value
    (:class:`RefusedValue`), as ``poise validate`` prints them."""

    def __init__(self, message, file=None, line=None, key=None, errors=None):
        super().__init__(message)
        self.file = file or None
        self.line = line or None
        self.key = key or None
        self.errors = list(errors) if errors else [RefusedValue(message, self.file, self.line, self.key)]


class PoiseWarning(UserWarning):
    """What Poise warns about an input it accepts (a rotor denser than lead, a test mass off the rotor)."""


def _warn_pending():
    for text in _poise.take_warnings():
        warnings.warn(text, PoiseWarning, stacklevel=4)  # at the caller of poise.run, poise.Study, ...


def _call(function, *args):
    try:
        return function(*args)
    except _poise.NativeError as e:
        category, message, file, line, key, errors = e.args[0] if len(e.args) == 1 else e.args
        if category == "input":
            if not file:  # "data.csv:12: ...": the message names where
                where = re.match(r"(?:\d+ errors? in the input:\s+)?([^\s:][^:\n]*):(\d+):", message)
                if where:
                    file, line = where.group(1), int(where.group(2))
            refused = [RefusedValue(r["message"], r["file"] or None, r["line"] or None, r["key"] or None,
                                    r["value"] or None, r["expected"] or None) for r in errors]
            raise InputError(message, file, line, key, refused) from None
        if category == "interrupt":
            raise KeyboardInterrupt(message) from None
        raise Error(message) from None
    finally:
        _warn_pending()


def _count(name, value, least):
    """None, or a whole number >= least (not a bool, not 10.5)."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least:
        raise InputError(f"{name}={value!r}: expected a whole number >= {least}", key=name)
    return int(value)


def _overrides(overrides):
    if overrides is None:
        return {}
    if not isinstance(overrides, dict):
        raise InputError("overrides: expected a dict of key -> value with its unit, e.g. "
                         "{\"yaw.bearing_span\": \"70 mm\"}")
    return {str(k): str(v) for k, v in overrides.items()}


class Result:
    """One run: its samples as arrays (one value per sample, in sample order) and its summary.

    ``outputs`` and ``inputs``: dict name -> numpy float64 array (a failed sample's outputs
    are NaN; ``ok`` and ``messages`` say which failed and why). ``units``: dict name -> unit.
    ``summary``: summary.json as a dict (requirements and answer included). ``path``: the
    result folder, or None when the run was made with ``out=None``.
    """

    def __init__(self, raw):
        self.inputs = dict(raw["inputs"])
        self.outputs = dict(raw["outputs"])
        self.units = dict(raw["units"])
        self.sample = raw["sample"].astype(np.int64)
        self.ok = raw["ok"]
        self.messages = list(raw["messages"])
        self.summary = raw["summary"]
        self.path = raw["path"]

    @property
    def answer(self):
        """The run's answer in words (summary.json "answer"); "" when it has none."""
        return self.summary.get("answer", "")

    def __repr__(self):
        n = len(self.sample)
        return f"<poise.Result {n} samples, {len(self.outputs)} outputs, path={self.path!r}>"


def run(study, samples=None, seed=None, threads=0, overrides=None, plots=False, out=None, progress=False,
        sensitivity_base=0, model=None, allow_programs=False):
    """Runs a study file as ``poise run`` does and returns a :class:`Result`.

    samples, seed: override the file's [sampling]; threads: 0 = all cores (results do not
    depend on it); overrides: model keys (or study keys the kind allows) with their units, as
    ``poise run --set``; plots: make the report's gnuplot figures; out: the result folder
    (must not hold a run), None = nothing kept; progress: show progress on stderr;
    sensitivity_base: > 0 runs ``poise sensitivity --base N`` instead (Sobol indices with
    their intervals in ``summary["sensitivity"]``; samples is then set by the layout).
    model: for a study whose model file has ``kind = "python"``, the function f(inputs) ->
    outputs that computes it: inputs is a dict of NumPy arrays (a batch of samples, one array
    per parameter, in the unit its value is written in), and f returns a dict with an array (or
    a number) per declared output in its unit; a NaN is a sample without an answer, an exception
    fails the batch with its message. allow_programs: start the program a model file with
    ``kind = "external"`` names (only for a program you trust), as ``--allow-programs``.
    """
    if model is not None and not callable(model):
        raise InputError(f"model={model!r}: expected a function f(inputs) -> outputs", None, None, "model")
    samples, seed = _count("samples", samples, 1), _count("seed", seed, 0)
    threads, sensitivity_base = _count("threads", threads, 0), _count("sensitivity_base", sensitivity_base, 0)
    try:
        raw = _call(_poise.run, os.fspath(study), samples, seed, threads, _overrides(overrides), bool(plots),
                    None if out is None else os.fspath(out), bool(progress), sensitivity_base, model,
                    bool(allow_programs))
    except InputError as e:
        if str(e).startswith("--out "):  # the command line's words for this function's out=
            raise InputError("out=" + str(e)[len("--out "):], e.file, e.line, "out") from None
        raise
    return Result(raw)


def _poise_columns(names, columns, nominal):
    return [columns[name] if name in columns else nominal[j] for j, name in enumerate(names)]


class Study:
    """A study file, to evaluate its outputs at inputs you give (kinds that can: the seeker's
    LOS study, the closed-form kinds and the gimbal static-unbalance study without a drawn
    disk; :attr:`evaluates` says, :attr:`why_not` says why not).

    ``input_names``: the inputs, as samples.csv names them, each in the unit that ends its
    name (``input_units``); ``output_names`` and ``output_units``: the study's outputs.
    overrides: model keys with their units, as for :func:`run`. seed: of the draws a kind
    with randomness of its own gives point k (those of sample k of a run with that seed;
    default the file's [sampling] seed).
    """

    def __init__(self, path, overrides=None, seed=None):
        self._s = _call(_poise.Study, os.fspath(path), _overrides(overrides), seed)

    kind = property(lambda self: self._s.kind)
    file = property(lambda self: self._s.file)
    output_names = property(lambda self: list(self._s.output_names))
    output_units = property(lambda self: dict(self._s.output_units))
    output_descriptions = property(lambda self: dict(self._s.output_descriptions))
    evaluates = property(lambda self: self._s.evaluates)
    why_not = property(lambda self: self._s.why_not)

    @property
    def input_names(self):
        return list(_call(lambda: self._s.input_names))

    @property
    def input_units(self):
        return dict(zip(self.input_names, _call(lambda: self._s.input_units)))

    @property
    def has_own_randomness(self):
        """Whether a sample draws beyond its inputs (then point k gets sample k's draws)."""
        return _call(lambda: self._s.has_own_randomness)

    def nominal(self):
        """The nominal unit's inputs: dict name -> value (every deviation and magnitude zero)."""
        return dict(zip(self.input_names, _call(lambda: self._s.nominal())))

    def evaluate(self, inputs, threads=0):
        """Outputs at the given inputs, vectorized: ``inputs`` is a dict name -> array (all of
        one length; scalars broadcast; inputs left out stay at nominal) or a 2-D array with one
        column per input in ``input_names`` order. Returns dict output name -> array. A point
        without a physical answer gets NaN outputs; ``last_failures`` lists (point, reason)."""
        names = self._names()
        if isinstance(inputs, dict):
            unknown = [k for k in inputs if k not in self._index]
            if unknown:
                close = difflib.get_close_matches(unknown[0], names, n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                raise InputError(f"evaluate: {unknown[0]!r} is not an input of {self.file}{hint}; its inputs: "
                                 + ", ".join(names), key=unknown[0])
            columns = {}
            for k, v in inputs.items():
                try:
                    column = np.ascontiguousarray(v, dtype=np.float64)
                except (TypeError, ValueError):
                    raise InputError(f"evaluate: input {k!r} = {v!r}: expected numbers in {self.input_units[k]} "
                                     "(the unit that ends the input's name), not text", key=k) from None
                if column.ndim > 1:
                    raise InputError(f"evaluate: input {k!r} is a {column.ndim}-D array; expected one value per point "
                                     "(a 1-D array) or one value for all", key=k)
                columns[k] = column.reshape(-1)
            lengths = {c.size for c in columns.values() if c.size != 1}
            if len(lengths) > 1:
                raise InputError(f"evaluate: the input arrays differ in length ({sorted(lengths)})")
            n = lengths.pop() if lengths else 1
            # Read in place by the C++ loop: no points x inputs copy; a missing input is its
            # nominal value at every point.
            nominal = self._nominal_columns()
            args = (_poise_columns(names, columns, nominal), n, _count("threads", threads, 0))
            y, failed, first = _call(self._s.evaluate, *args)
        else:
            x = np.ascontiguousarray(inputs, dtype=np.float64)
            if x.ndim == 1:
                x = x.reshape(1, -1)
            if x.ndim != 2 or x.shape[1] != len(names):
                raise InputError(f"evaluate: expected a 2-D array with {len(names)} columns ({', '.join(names)})")
            y, failed, first = _call(self._s.evaluate_matrix, x, _count("threads", threads, 0))
        self.last_failures = list(first)
        self.failure_count = int(failed)
        return {name: y[:, k] for k, name in enumerate(self._outputs())}

    # What every evaluate needs, asked of Poise once.
    def _names(self):
        if not hasattr(self, "_cached_names"):
            self._cached_names = list(_call(lambda: self._s.input_names))
            self._index = {n: j for j, n in enumerate(self._cached_names)}
        return self._cached_names

    def _nominal_columns(self):
        if not hasattr(self, "_cached_nominal"):
            self._cached_nominal = [np.array([v], dtype=np.float64) for v in _call(lambda: self._s.nominal())]
        return self._cached_nominal

    def _outputs(self):
        if not hasattr(self, "_cached_outputs"):
            self._cached_outputs = list(_call(lambda: self._s.evaluator_outputs))
        return self._cached_outputs

    def __repr__(self):
        return f"<poise.Study {self.file!r} kind={self.kind!r}>"


def validate(study):
    """The study file and its model checked as ``poise validate`` checks them, nothing run: the
    same one-line summary. Refused input raises :class:`InputError` with every refused value in
    ``.errors``."""
    return _call(_poise.validate, os.fspath(study))


class Sample(typing.NamedTuple):
    """One sample recomputed alone (``poise replay``): ``index``, ``ok``, ``message`` (why it
    failed, else ""), ``inputs`` and ``outputs`` by name (the study's units), and ``details``:
    what else the kind gives, lists of records as dicts of NumPy arrays (the seeker's error at
    every grid point: ``details["grid"]["total_arcsec"]``)."""
    index: int
    ok: bool
    message: str
    inputs: dict
    outputs: dict
    details: dict


def _columns_of(value):
    """A list of records with the same numeric keys as a dict of NumPy arrays; else as it is."""
    if (isinstance(value, list) and value and all(isinstance(r, dict) for r in value)
            and all(r.keys() == value[0].keys() for r in value)
            and all(isinstance(v, (int, float)) for r in value for v in r.values())):
        return {k: np.array([r[k] for r in value], dtype=float) for k in value[0]}
    return value


def replay(study, sample, samples=None, seed=None):
    """Sample ``sample`` of the study recomputed alone, as ``poise replay -i`` does (with the
    run's ``samples`` and ``seed`` where they differ from the study file's): a :class:`Sample`."""
    j = _call(_poise.replay, os.fspath(study), _count("sample", sample, 0), _count("samples", samples, 1),
              None if seed is None else _count("seed", seed, 0))
    details = {k: _columns_of(v) for k, v in j.items() if k not in ("sample", "status", "message", "inputs", "outputs")}
    return Sample(j["sample"], j["status"] == "ok", j.get("message", ""), j.get("inputs", {}), j.get("outputs", {}),
                  details)


class Optimization(typing.NamedTuple):
    """An optimization run (``poise optimize``): ``answer`` in words, ``verified`` (the optimum
    passed its check on fresh samples), ``exit_status`` (the command's: 0 verified, 3 not),
    ``summary`` (summary.json as a dict: optimum, verification, nearest passing design, ...) and
    ``path`` (the result folder; None with ``out=None``)."""
    answer: str
    verified: bool
    exit_status: int
    summary: dict
    path: typing.Optional[str]


def optimize(file, out=None, threads=0, seed=None, plots=False, progress=False):
    """An optimization file (docs/designer.md) run as ``poise optimize`` runs it: an
    :class:`Optimization`. A design that fails its fresh-sample check is an answer, not an
    error (``verified`` False); no feasible design raises :class:`Error`."""
    r = _call(_poise.optimize, os.fspath(file), None if out is None else os.fspath(out), _count("threads", threads, 0),
              None if seed is None else _count("seed", seed, 0), bool(plots), bool(progress))
    return Optimization(r["answer"], r["exit_status"] == 0, r["exit_status"], r["summary"], r["path"])


def _role_pairs(d):
    return [f"{role}={value}" for role, value in (d or {}).items()]


class SineFit(typing.NamedTuple):
    """A measured torque table's sine fit M(theta) = MT_s sin(theta + b) + MK (``poise fit``), in
    the table's torque ``unit``: ``amplitude`` (MT_s), ``phase_deg`` (b), ``offset`` (MK),
    ``standard_errors`` of the three, ``rmse``, ``sigma``, ``max_abs_residual``, ``n_points`` and
    ``residuals``: NumPy arrays ``theta_deg``, ``measured``, ``fitted``, ``residual``."""
    amplitude: float
    phase_deg: float
    offset: float
    standard_errors: dict
    rmse: float
    sigma: float
    max_abs_residual: float
    unit: str
    n_points: int
    residuals: dict


def fit(data, columns=None, units=None):
    """A measured torque table fitted as ``poise fit --json`` fits it: a :class:`SineFit`.
    columns, units: the file's own column names and units by role, as ``--column`` and
    ``--unit`` take them (roles: angle, torque, time, sweep)."""
    j = _call(_poise.fit, os.fspath(data), _role_pairs(columns), _role_pairs(units))
    return SineFit(j["amplitude"], j["phase_deg"], j["offset"], j["standard_errors"], j["rmse"], j["sigma"],
                   j["max_abs_residual"], j["unit"], j["n_points"], _columns_of(j["residuals"]))


class RecordDiagnosis(typing.NamedTuple):
    """A raw record's diagnosis (``poise diagnose-record``): ``answer`` in one sentence,
    ``json`` (the ``--json`` object as a dict: the motion, each effect found, the parameters
    the motion can show), ``text`` (what the command prints before the answer), and NumPy
    arrays ``angle``, ``residual_before`` and ``residual_after`` (the residual against angle
    before and after the effects found)."""
    answer: str
    json: dict
    text: str
    angle: np.ndarray
    residual_before: np.ndarray
    residual_after: np.ndarray


def diagnose_record(record, kt="0.05 N*m/A", columns=None, units=None):
    """A raw record (time, drive current or torque, angle) diagnosed as ``poise diagnose-record``
    does: a :class:`RecordDiagnosis`. kt: the torque constant with its unit; columns, units: the
    file's own column names and units by role (time, current, torque, angle, velocity)."""
    r = _call(_poise.diagnose_record, os.fspath(record), str(kt), _role_pairs(columns), _role_pairs(units))
    return RecordDiagnosis(r["json"]["answer"], r["json"], r["text"], r["angle"], r["residual_before"],
                           r["residual_after"])


def error_mechanisms(folder="data/yang2015", calibrate=None, draws=20000):
    """Which per-test error mechanism a folder of measured static-unbalance tables supports, as
    ``poise error-mechanisms FOLDER --json`` gives it (that object as a dict; "supported" names
    the mechanism). calibrate: list this table first; draws: simulated copies per check."""
    return _call(_poise.error_mechanisms, os.fspath(folder), calibrate or "", _count("draws", draws, 100))


def sensitivity(study, base, seed=None, threads=0, overrides=None, out=None, progress=False, model=None,
                allow_programs=False):
    """Sobol indices of a study as ``poise sensitivity --base N`` computes them: a :class:`Result`
    whose ``summary["sensitivity"]`` holds each index with its interval."""
    return run(study, seed=seed, threads=threads, overrides=overrides, out=out, progress=progress,
               sensitivity_base=_count("base", base, 1), model=model, allow_programs=allow_programs)


def balance(campaign, out=None):
    """A balancing campaign's readings analysed as ``poise balance --json`` does (that object as
    a dict): influence coefficients, the correction with its 95% regions, each check run and run
    of unknown masses, the tests of the linear model, and "answer" in one sentence. out: a folder
    for balance.json and report.html, as ``--out``. The campaign file: docs/balancing.md."""
    return _call(_poise.balance, os.fspath(campaign), "" if out is None else os.fspath(out))


def budget(path):
    """An error budget checked as ``poise budget --json`` does: that object as a dict."""
    return _call(_poise.budget, os.fspath(path))


def mass_properties(meshes, unit, density, rays=256, drop_duplicates=False, weld=None, max_overlap=None):
    """Mass properties of CAD meshes as ``poise mass-properties --json`` gives them (with a
    "warnings" list). meshes: a path or a list; unit: "mm", "cm", "m" or "in", or one per mesh;
    density: one string with its unit ("2700 kg/m^3") or one per mesh; drop_duplicates: remove triangles
    exported twice (and say so in "warnings") instead of refusing the mesh; weld: the weld
    tolerance with its unit ("0.0001 mm"; "0" none; None the default, 1e-6 of the part's size);
    max_overlap: the overlap of shells accepted, a share of the part's volume (None the default, 1e-6)."""
    if isinstance(meshes, (str, os.PathLike)):
        meshes = [meshes]
    densities = [density] if isinstance(density, str) else list(density) if isinstance(density, (list, tuple)) else None
    if not densities or not all(isinstance(d, str) for d in densities):
        raise InputError(f"density={density!r}: expected a density with its unit, e.g. \"2700 kg/m^3\", or a list of "
                         "them, one per mesh", key="density")
    units = [unit] if isinstance(unit, str) else list(unit) if isinstance(unit, (list, tuple)) else None
    if not units or not all(isinstance(u, str) for u in units):
        raise InputError(f"unit={unit!r}: expected \"mm\", \"cm\", \"m\" or \"in\", or a list of them, one per "
                         "mesh", key="unit")
    return _call(_poise.mass_properties, [os.fspath(m) for m in meshes], units, densities,
                 _count("rays", rays, 1), bool(drop_duplicates), "" if weld is None else str(weld),
                 "" if max_overlap is None else str(max_overlap))


def diagnose(data, alpha=0.05, max_harmonic=6, noise=None, load_torque=None, load_angle=None, study=None,
             study_samples=64, columns=None, units=None):
    """A measured static-unbalance table diagnosed as ``poise diagnose --json`` does.

    columns, units: the file's own column names and units by role, as ``--column`` and ``--unit``
    take them, e.g. ``columns={"angle": "angle [rad]", "torque": "M"}, units={"torque": "N*m"}``
    (roles: angle, torque, time, sweep, torque_se)."""
    return _call(_poise.diagnose, os.fspath(data), float(alpha), int(max_harmonic), noise or "",
                 load_torque or "", load_angle or "", "" if study is None else os.fspath(study),
                 int(study_samples), _role_pairs(columns), _role_pairs(units))
