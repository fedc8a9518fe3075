"""Multibody dynamics from Dyad model files.

Load a model (``load`` a ``.dyad`` file, or ``loads`` its text), then
``Model.simulate`` it, with other parameters, start values and options if
you like, and read every signal of the result by name as a numpy array
(``result["link1.joint.phi"]``, ``result.time``), or as a pandas or polars
DataFrame. ``Model.sweep`` runs many sets of values on every core (``grid`` makes
every combination of values of several parameters). ``Simulator`` (or
``Model.simulator``) steps a model on request while Python sets its inputs
(a model's top-level ``RealInput``s) and reads its outputs and state: a
controller in the loop. ``Model.linearize`` (or ``Simulator.linearize``)
gives the linear model around an operating point (the start, a steady
state, or a time along a simulation) as a ``LinearModel``: numpy ``A``,
``B``, ``C``, ``D`` with the names of their coordinates, inputs and
outputs, ready for python-control (``LinearModel.to_control()``).

Parameters and start values are named by their path in the model, as in
the model file: ``length`` (a parameter of the model itself),
``link1.length`` (of a component in it), ``rev.phi`` (a start value, in
``initial=``).

Errors are exceptions: ``ModelError`` for mistakes in the model files
(with ``file``, ``line`` and ``column``), ``SimulationError`` for a
simulation that stopped part way (with ``time`` and the ``partial``
result), ``LinearizationError`` for an operating point without a linear
model or a steady state that was not found, ``ValueError`` for options and
names that cannot be used. All derive from
``MultibodyError`` except ``ValueError``.
"""

from __future__ import annotations

import fnmatch
import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _multibody
from ._multibody import LinearizationError, ModelError, MultibodyError, SimulationError

__all__ = [
    "load",
    "loads",
    "grid",
    "Model",
    "Result",
    "Simulator",
    "JointSpace",
    "LinearModel",
    "MultibodyError",
    "LinearizationError",
    "ModelError",
    "SimulationError",
]


class Result:
    """The samples of one simulation.

    ``time`` is a numpy array of the sample times; ``result[name]`` the
    samples of one signal (``result["body.r_0[2]"]``); ``names`` lists the
    signals kept; ``values`` is the whole table (one row per time, one
    column per name); ``warnings`` says what the integrator found doubtful.
    """

    def __init__(self, names: Sequence[str], time: bytes, values: bytes, warnings: Sequence[str]):
        self.names: List[str] = list(names)
        self.time: np.ndarray = np.frombuffer(time, dtype=np.float64)
        self.values: np.ndarray = np.frombuffer(values, dtype=np.float64).reshape(len(self.time), len(self.names))
        self.warnings: List[str] = list(warnings)
        self._index = {name: k for k, name in enumerate(self.names)}

    def __getitem__(self, name: str) -> np.ndarray:
        if name == "time":
            return self.time
        try:
            return self.values[:, self._index[name]]
        except KeyError:
            close = [n for n in self.names if n.split("[")[0] == name.split("[")[0]][:5]
            hint = f"; did you mean {', '.join(close)}?" if close else "; pass signals=[...] to simulate() to keep it"
            raise KeyError(f"no signal {name!r} in this result{hint}") from None

    def __contains__(self, name: object) -> bool:
        return name in self._index

    def __len__(self) -> int:
        return len(self.time)

    def __repr__(self) -> str:
        span = f"t = {self.time[0]} .. {self.time[-1]}" if len(self.time) else "empty"
        return f"<multibody.Result: {len(self.names)} signals, {len(self.time)} samples, {span}>"

    def to_pandas(self):
        """The samples as a pandas DataFrame: a ``time`` column, then one per signal."""
        import pandas as pd

        frame = pd.DataFrame(self.values, columns=self.names)
        frame.insert(0, "time", self.time)
        return frame

    def to_parquet(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes the samples to a Parquet file (needs pyarrow), with the
        columns of the command's CSV: ``time``, then one per signal."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        columns = {"time": self.time, **{n: self.values[:, k] for k, n in enumerate(self.names)}}
        pq.write_table(pa.table(columns), os.fspath(path))

    def to_polars(self):
        """The samples as a polars DataFrame: a ``time`` column, then one per signal."""
        import polars as pl

        return pl.DataFrame({"time": self.time, **{n: self.values[:, k] for k, n in enumerate(self.names)}})


class Model:
    """A loaded model: the analysis (or component) to simulate, with its options."""

    def __init__(self, native: "_multibody.Model", file: str):
        self._native = native
        self.file = file
        self._all: Optional[List[str]] = None

    @property
    def name(self) -> str:
        """The analysis's name (or the component's, without an analysis)."""
        return self._native.name

    @property
    def options(self) -> Dict[str, float]:
        """The analysis's options: start, stop, abstol, reltol, saveat, dtmax."""
        return dict(self._native.options)

    def joint_space(self, params: Optional[Mapping[str, float]] = None) -> "JointSpace":
        """The model's dynamics by joint coordinate, as robotics libraries
        give them (mass matrix, forward and inverse dynamics, frame poses),
        with these parameter values; for models without loops."""
        return JointSpace(_call(self._native.joint_space, list((params or {}).items())))

    def signals(self, *patterns: str) -> List[str]:
        """Every signal's name, or those matching the glob patterns (``"*.phi"``)."""
        names = self._every_signal()
        if not patterns:
            return list(names)
        return [n for n in names if any(_glob(n, p) for p in patterns)]

    def simulate(
        self,
        params: Optional[Mapping[str, float]] = None,
        initial: Optional[Mapping[str, float]] = None,
        *,
        signals: Union[None, str, Sequence[str]] = None,
        stop: Optional[float] = None,
        saveat: Optional[float] = None,
        abstol: Optional[float] = None,
        reltol: Optional[float] = None,
        alg: Optional[str] = None,
    ) -> Result:
        """Simulates the model and returns its samples.

        ``params`` and ``initial`` map paths to values (``{"body.m": 2}``,
        ``{"rev.phi": 0.3}``); they win over the model files. ``signals``
        picks what is kept: names or glob patterns (``"*.phi"``), ``"all"``
        for every signal; by default the states. The options default to the
        analysis's; ``alg`` is ``"auto"``, ``"Rodas4"`` (stiff models) or
        ``"RK4"``. Raises ``SimulationError`` (with the partial result) if
        the simulation stops part way. Ctrl-C stops it after its current
        step with ``KeyboardInterrupt``, whose ``partial`` holds what was
        computed (and ``time`` where it stopped).
        """
        names = self._signal_names(signals)
        columns = _call(
            self._native.simulate,
            _pairs(params, "params"),
            _pairs(initial, "initial"),
            names,
            stop=stop,
            saveat=saveat,
            abstol=abstol,
            reltol=reltol,
            alg=alg,
        )
        return Result(*columns)

    def sweep(
        self,
        sets: Iterable[Mapping[str, float]],
        initial: Optional[Iterable[Mapping[str, float]]] = None,
        *,
        signals: Union[None, str, Sequence[str]] = None,
        threads: Optional[int] = None,
        stop: Optional[float] = None,
        saveat: Optional[float] = None,
        abstol: Optional[float] = None,
        reltol: Optional[float] = None,
        alg: Optional[str] = None,
    ) -> List[Union[Result, MultibodyError, ValueError]]:
        """Simulates once per set of parameter values, on ``threads`` threads
        (all cores by default), and returns one entry per set, in order: its
        ``Result``, or the exception it raised (the others are kept).

        ``initial``, when given, is a list of start values of the same length.

        Ctrl-C stops the runs under way with ``KeyboardInterrupt``, whose
        ``results`` holds the entries of the finished runs and ``None`` for
        the others.
        """
        sets = [dict(s) for s in sets]
        starts = [dict(s) for s in initial] if initial is not None else [{} for _ in sets]
        if len(starts) != len(sets):
            raise ValueError(f"{len(sets)} sets of parameters but {len(starts)} sets of start values")
        names = self._signal_names(signals)
        pairs = [(_pairs(p, "params"), _pairs(i, "initial")) for p, i in zip(sets, starts)]
        def entries(out: list) -> list:
            return [
                None if r is None else _wrap_error(r) if isinstance(r, BaseException) else Result(*r) for r in out
            ]

        try:
            out = self._native.sweep(
                pairs, names, threads=threads, stop=stop, saveat=saveat, abstol=abstol, reltol=reltol, alg=alg
            )
        except KeyboardInterrupt as e:
            if len(e.args) == 2:
                message, out = e.args
                e.message, e.results = message, entries(out)
                e.args = (message,)
            raise
        return entries(out)

    def simulator(
        self,
        params: Optional[Mapping[str, float]] = None,
        initial: Optional[Mapping[str, float]] = None,
        *,
        stop: Optional[float] = None,
        saveat: Optional[float] = None,
        abstol: Optional[float] = None,
        reltol: Optional[float] = None,
        alg: Optional[str] = None,
    ) -> "Simulator":
        """A ``Simulator`` of this model with these values and options."""
        return Simulator(
            self, params, initial, stop=stop, saveat=saveat, abstol=abstol, reltol=reltol, alg=alg
        )

    def linearize(
        self,
        params: Optional[Mapping[str, float]] = None,
        initial: Optional[Mapping[str, float]] = None,
        *,
        inputs: Optional[Sequence[str]] = None,
        outputs: Optional[Sequence[str]] = None,
        at: Union[str, float] = "start",
        derivatives: str = "auto",
        free_inputs: Sequence[str] = (),
        fixed_outputs: Optional[Mapping[str, float]] = None,
        stop: Optional[float] = None,
        abstol: Optional[float] = None,
        reltol: Optional[float] = None,
        alg: Optional[str] = None,
    ) -> "LinearModel":
        """The linear model of this model with these values, around an
        operating point: ``at="start"``, ``at="steady"`` (a steady state
        found from the start; ``free_inputs`` may move, holding as many
        ``fixed_outputs`` at their values), or ``at=t`` (a number: after
        simulating to ``t``). ``inputs`` and ``outputs`` name the columns
        of B and the rows of C (default: all the model's inputs, and its
        outputs; outputs may be any variable). ``derivatives`` is
        ``"auto"``, ``"exact"`` or ``"differences"``."""
        sim = self.simulator(params, initial, stop=stop, abstol=abstol, reltol=reltol, alg=alg)
        if at == "steady":
            sim.steady_state(free_inputs, fixed_outputs)
        elif isinstance(at, (int, float)) and not isinstance(at, bool):
            sim.step_until(float(at))
        elif at != "start":
            raise ValueError(f"at={at!r}: use \"start\", \"steady\" or a time")
        return sim.linearize(inputs=inputs, outputs=outputs, derivatives=derivatives)

    def _signal_names(self, signals: Union[None, str, Sequence[str]]) -> List[str]:
        return _pick(signals, self._every_signal())

    def _every_signal(self) -> List[str]:
        # Parameters may change values, not which signals a model has.
        if self._all is None:
            self._all = self._native.signals()
        return self._all

    def __repr__(self) -> str:
        return f"<multibody.Model {self.name!r} from {self.file}>"


class JointSpace:
    """A mechanism's dynamics by joint coordinate (``Model.joint_space()``).

    ``q`` are the position coordinates (``coordinates``: ``elbow.phi``, or a
    floating base's ``r_0`` and quaternion ``Q_hat`` [w, i, j, k]) and
    ``v`` the velocity coordinates (``velocities``: ``elbow.w``, or a
    floating base's ``v_0`` in the world and ``w_a`` in the body), in tree
    order. Forces ``tau`` are joint torques and forces (a floating base's: a
    world force and a body torque); the model's own joint forces (springs,
    dampers) and gravity are in the dynamics already.
    """

    def __init__(self, native: "_multibody.JointSpace"):
        self._native = native

    @property
    def joints(self) -> List[str]:
        """The joints (the floating base by its link), in tree order."""
        return self._native.joints

    @property
    def coordinates(self) -> List[str]:
        """The names of the position coordinates ``q``."""
        return self._native.coordinates

    @property
    def velocities(self) -> List[str]:
        """The names of the velocity coordinates ``v`` (and of ``a`` and ``tau``)."""
        return self._native.velocities

    def mass_matrix(self, q: Sequence[float]) -> np.ndarray:
        """``M(q)``, ``nv x nv``."""
        n = len(self.velocities)
        return np.array(_call(self._native.mass_matrix, _floats(q)), dtype=float).reshape(n, n)

    def forward_dynamics(self, q: Sequence[float], v: Sequence[float], tau: Optional[Sequence[float]] = None) -> np.ndarray:
        """The accelerations at ``(q, v)`` under the joint forces ``tau`` (none by default)."""
        tau = np.zeros(len(self.velocities)) if tau is None else tau
        return np.array(_call(self._native.forward_dynamics, _floats(q), _floats(v), _floats(tau)))

    def inverse_dynamics(self, q: Sequence[float], v: Sequence[float], a: Sequence[float]) -> np.ndarray:
        """The joint forces that give the accelerations ``a`` at ``(q, v)``."""
        return np.array(_call(self._native.inverse_dynamics, _floats(q), _floats(v), _floats(a)))

    def frame_pose(self, frame: str, q: Sequence[float]) -> Tuple[np.ndarray, np.ndarray]:
        """The origin (world coordinates) and ``R`` (``v_frame = R v_world``)
        of a frame at ``q``: a link or component's name, or a connector
        (``elbow.frame_b``)."""
        r, rotation = _call(self._native.frame_pose, frame, _floats(q))
        return np.array(r), np.array(rotation).reshape(3, 3)

    def __repr__(self) -> str:
        return f"<JointSpace of {len(self.joints)} joints, {len(self.coordinates)} + {len(self.velocities)} coordinates>"


def _floats(x: Sequence[float]) -> List[float]:
    return [float(v) for v in np.asarray(x, dtype=float).ravel()]


class Simulator:
    """A model being simulated, advanced on request: a controller (or any
    host) sets its inputs, steps it, and reads its outputs and state
    between steps.

    ``Simulator(model, params, initial, stop=..., saveat=..., reltol=...,
    abstol=..., alg=...)`` takes a ``Model`` (or a path to a ``.dyad``
    file) and the values and options of ``Model.simulate``; it starts at the
    model's start values and the analysis's start time.

    ``step_until(t)`` integrates to exactly ``t`` (the GIL released),
    handling events on the way and recording the samples of the output
    grid (every ``saveat``); ``set_input(name, value)`` sets an input (a
    top-level ``RealInput`` of the model), held until set again (a
    zero-order hold); ``outputs`` and ``inputs`` are dictionaries by name;
    ``state`` is a numpy array in the order of ``state_names``;
    ``get(name)`` reads any variable (any column of a result) now;
    ``result()`` gives the samples recorded so far as a ``Result``.

    A bad name raises ``ValueError`` with the name it probably meant; a
    simulation that stops part way raises ``SimulationError`` (with
    ``time`` and the ``partial`` result), and the simulator stays at the
    last good time.
    """

    def __init__(
        self,
        model: Union["Model", str, "os.PathLike[str]"],
        params: Optional[Mapping[str, float]] = None,
        initial: Optional[Mapping[str, float]] = None,
        *,
        stop: Optional[float] = None,
        saveat: Optional[float] = None,
        abstol: Optional[float] = None,
        reltol: Optional[float] = None,
        alg: Optional[str] = None,
    ):
        if not isinstance(model, Model):
            model = load(model)
        self.model = model
        self._native = _call(
            model._native.simulator,
            _pairs(params, "params"),
            _pairs(initial, "initial"),
            stop=stop,
            saveat=saveat,
            abstol=abstol,
            reltol=reltol,
            alg=alg,
        )
        self._all: Optional[List[str]] = None

    def step_until(self, t: float) -> None:
        """Integrates to exactly ``t`` (not before the time reached).

        Ctrl-C stops it after its current step with ``KeyboardInterrupt``
        (``time`` where it stopped, ``partial`` the states recorded); the
        simulator stays there and can go on.
        """
        try:
            self._native.step_until(t)
        except (MultibodyError, KeyboardInterrupt) as e:
            raise _wrap_error(e) from None

    def set_input(self, name: str, value: float) -> None:
        """Sets the input ``name``; it holds the value until set again."""
        self._native.set_input(name, _number(value, f"the input {name!r}"))

    @property
    def inputs(self) -> Dict[str, float]:
        """The inputs and the values they hold now."""
        return dict(self._native.inputs())

    @property
    def outputs(self) -> Dict[str, float]:
        """The outputs (top-level ``RealOutput``s) at the time reached."""
        return dict(self._native.outputs())

    @property
    def time(self) -> float:
        """The time reached."""
        return self._native.time()

    @property
    def state(self) -> np.ndarray:
        """The state reached (a copy), in the order of ``state_names``."""
        return np.array(self._native.state())

    @state.setter
    def state(self, y: Sequence[float]) -> None:
        self.set_state(y)

    def set_state(self, y: Union[Sequence[float], Mapping[str, float]]) -> None:
        """Sets the whole state (an array in the order of ``state_names``), or
        some states by name (a dict); the integrator starts again from it."""
        if isinstance(y, Mapping):
            for name, value in y.items():
                self._native.set_state_value(str(name), _number(value, f"the state {name!r}"))
        else:
            try:
                values = np.asarray(y, dtype=np.float64).ravel()
            except (TypeError, ValueError):
                raise TypeError(f"set_state takes numbers (or a dict of names to numbers), not {y!r}") from None
            self._native.set_state([float(v) for v in values])

    @property
    def state_names(self) -> List[str]:
        return self._native.state_names()

    def get(self, name: str) -> float:
        """Any variable of the model (any column of a result) now."""
        return self._native.get(name)

    def signals(self, *patterns: str) -> List[str]:
        """Every signal's name, or those matching the glob patterns."""
        names = self._every_signal()
        return [n for n in names if not patterns or any(_glob(n, p) for p in patterns)]

    def result(self, signals: Union[None, str, Sequence[str]] = None) -> Result:
        """The samples recorded so far; ``signals`` as in ``Model.simulate``
        (the states by default, ``"all"``, names or glob patterns)."""
        return Result(*self._native.result(_pick(signals, self._every_signal())))

    def reset(self) -> None:
        """Back to the start: state, time and inputs; the samples are dropped."""
        _call(self._native.reset)

    @property
    def event_count(self) -> int:
        """How many events were handled so far."""
        return self._native.event_count()

    def linearize(
        self,
        *,
        inputs: Optional[Sequence[str]] = None,
        outputs: Optional[Sequence[str]] = None,
        derivatives: str = "auto",
    ) -> "LinearModel":
        """The linear model at the time and state reached, with the inputs
        as set (see ``Model.linearize``)."""
        names, matrices, rest = self._native.linearize(
            None if inputs is None else list(inputs),
            None if outputs is None else list(outputs),
            derivatives,
        )
        return LinearModel(names, matrices, rest)

    def steady_state(
        self,
        free_inputs: Sequence[str] = (),
        fixed_outputs: Optional[Mapping[str, float]] = None,
        *,
        abstol: float = 1e-8,
        reltol: float = 1e-8,
    ) -> Dict[str, Any]:
        """Moves to a steady state near the state reached, by Newton's
        method on the rates (Dyad's SteadyStateAnalysis tolerances), with
        ``free_inputs`` free to move and as many ``fixed_outputs`` held.
        Returns the largest rate left, the Newton steps taken and the free
        inputs' values; raises ``LinearizationError`` naming the rates that
        did not settle when there is none near."""
        residual, iterations, values = self._native.steady_state(
            list(free_inputs), _pairs(fixed_outputs, "fixed_outputs"), abstol, reltol
        )
        return {"residual": residual, "iterations": iterations, "inputs": dict(values)}

    def _every_signal(self) -> List[str]:
        if self._all is None:
            self._all = self._native.signals()
        return self._all

    def __repr__(self) -> str:
        return f"<multibody.Simulator {self.model.name!r} at t = {self.time}>"


class LinearModel:
    """``dx' = A dx + B du``, ``dy = C dx + D du`` around an operating
    point: ``A``, ``B``, ``C``, ``D`` are numpy arrays; ``states``,
    ``inputs`` and ``outputs`` name their coordinates (a quaternion stands
    as ``body.rotation[1..3]``; in a loop only the independent joints).
    ``exact`` says whether A and B came from analytic derivatives;
    ``accuracy`` is their largest difference from central differences
    (relative to the largest entry), when both were taken; ``rates`` are
    the coordinates' rates at the point (zero at an equilibrium)."""

    def __init__(self, names, matrices, rest):
        self.states, self.inputs, self.outputs = (list(n) for n in names)
        shapes = [
            (len(self.states), len(self.states)),
            (len(self.states), len(self.inputs)),
            (len(self.outputs), len(self.states)),
            (len(self.outputs), len(self.inputs)),
        ]
        self.A, self.B, self.C, self.D = (
            np.array(m, dtype=float).reshape(shape) for m, shape in zip(matrices, shapes)
        )
        self.exact, self.accuracy, self.notes, rates, self.time = rest
        self.rates = np.array(rates, dtype=float)

    def poles(self) -> np.ndarray:
        """The eigenvalues of ``A``."""
        return np.linalg.eigvals(self.A) if self.A.size else np.zeros(0, dtype=complex)

    def to_control(self):
        """The model as a ``control.StateSpace`` with its names (needs python-control)."""
        import control

        return control.ss(
            self.A, self.B, self.C, self.D, states=self.states, inputs=self.inputs, outputs=self.outputs
        )

    def __repr__(self) -> str:
        how = "exact" if self.exact else "differences"
        return (
            f"<multibody.LinearModel: {len(self.states)} states, {len(self.inputs)} inputs, "
            f"{len(self.outputs)} outputs, at t = {self.time} ({how})>"
        )


def load(
    path: Union[str, "os.PathLike[str]"],
    *,
    analysis: Optional[str] = None,
    model: Optional[str] = None,
    floating: bool = False,
) -> Model:
    """Loads a ``.dyad`` file: its analysis (``analysis=`` when it has
    several), or a component with default options (``model=``). A folder
    is read as ``multibody run`` reads one: every ``.dyad`` file in it
    (not its subfolders), together. A ``.urdf`` file is read as
    ``multibody import`` writes it (a fixed base, or a floating one with
    ``floating=True``; mesh visuals left out), with gravity along -z."""
    path = os.fspath(path)
    if os.path.isdir(path):
        files = sorted(os.path.join(path, f) for f in os.listdir(path) if f.endswith(".dyad"))
        if not files:
            raise ModelError(f"{path} is a folder without .dyad files", path, 0, 0)
        sources = [(f, _read_text(f)) for f in files]
        return Model(_call(_multibody.load_sources, sources, analysis=analysis, model=model), path)
    text = _read_text(path)
    if path.lower().endswith(".urdf"):
        return Model(_call(_multibody.load_urdf, text, path, floating=floating), path)
    return loads(text, file=path, analysis=analysis, model=model)


def _read_text(path: str) -> str:
    """The UTF-8 text of a file, or a ModelError that names it."""
    with open(path, "rb") as f:
        data = f.read()
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise ModelError(f"{path} is not UTF-8 text (byte offset {e.start})", path, 0, 0) from None


def loads(text: str, *, file: str = "<text>", analysis: Optional[str] = None, model: Optional[str] = None) -> Model:
    """Loads a model from its ``.dyad`` text; ``file`` names it in messages."""
    return Model(_call(_multibody.load_text, text, file, analysis=analysis, model=model), file)


def grid(axes: Mapping[str, Iterable[float]]) -> List[Dict[str, float]]:
    """Every combination of the values of each path, the first path slowest,
    for ``Model.sweep``: ``grid({"body.m": [1, 2], "damper.d": [0, 0.1]})``
    gives four sets."""
    sets: List[Dict[str, float]] = [{}]
    for path, values in axes.items():
        values = [float(v) for v in values]
        sets = [{**s, path: v} for s in sets for v in values]
    return sets


def _pick(signals: Union[None, str, Sequence[str]], everything: List[str]) -> List[str]:
    """The names ``signals`` selects: none (the states), ``"all"``, names or patterns."""
    if signals is None:
        return []
    if isinstance(signals, str):
        signals = [signals]
    if list(signals) == ["all"]:
        return list(everything)
    chosen: List[str] = []
    for pattern in signals:
        matches = [n for n in everything if _glob(n, pattern)]
        if not matches:
            raise ValueError(f"no signal matches {pattern!r}; Model.signals() lists them")
        chosen.extend(m for m in matches if m not in chosen)
    return chosen


def _glob(name: str, pattern: str) -> bool:
    """``*`` and ``?`` as in the command's ``--signals``; brackets are literal
    (signal names hold them: ``body.r_0[2]``)."""
    return fnmatch.fnmatchcase(name, pattern.replace("[", "[[]"))


def _pairs(values: Optional[Mapping[str, float]], argument: str) -> List[tuple]:
    if values is None:
        return []
    if not isinstance(values, Mapping):
        raise TypeError(
            f"{argument} maps names to numbers, like {{\"body.m\": 2.0}}; got {type(values).__name__} {values!r}"
        )
    return [(str(k), _number(v, f"{argument}[{k!r}]")) for k, v in values.items()]


def _number(value, what: str) -> float:
    """``value`` as a float, or an error that names ``what`` it was given for."""
    try:
        return float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{what} must be a number, not {type(value).__name__} {value!r}") from None
    except OverflowError:
        raise ValueError(f"{what} = {value!r} is too large for a double") from None


def _call(function, *args, **kwargs):
    try:
        return function(*args, **kwargs)
    except (MultibodyError, KeyboardInterrupt) as e:
        raise _wrap_error(e) from None


def _wrap_error(e: BaseException) -> BaseException:
    """Gives the native exceptions their named attributes."""
    if isinstance(e, ModelError) and len(e.args) == 4:
        message, file, line, column = e.args
        e.message, e.file, e.line, e.column = message, file, line, column
    elif isinstance(e, (SimulationError, KeyboardInterrupt)) and len(e.args) == 3:
        message, time, partial = e.args
        e.message, e.time = message, time
        e.partial = Result(*partial) if partial is not None else None
        # A KeyboardInterrupt prints its arguments: the message alone.
        e.args = (message, time) if isinstance(e, SimulationError) else (message,)
    return e


def _message(self) -> str:
    return str(self.args[0]) if self.args else ""


# The message alone, not the tuple of arguments.
ModelError.__str__ = _message
SimulationError.__str__ = _message
