"""Readings of the paper: the choices it leaves open (:class:`Reading`), each justified by
its own text. :data:`HEADLINE` is the paper's own evaluation, fixed from the text before any
verdict was computed; every other reading changes one choice of it."""

from __future__ import annotations

from dataclasses import dataclass

from ..constitutive.dynamics import evaluation
from ..parameters import LABELLINGS, Mud, paper_mud
from ..terrains import MudTerrain
from ..trajectories import FOOT_HEIGHT, STANCE_DEPTH

#: Stance depths of the depth dimension [m]: 10-26 mm by 1 mm, up to the fixed feet's height.
STANCE_DEPTHS = tuple(mm / 1000 for mm in range(10, round(FOOT_HEIGHT * 1000) + 1))
#: Pad-curl delays of the morphing foot's sensitivity [s]: 0-100 ms by 10 ms.
CURL_DELAYS = tuple(ms / 1000 for ms in range(0, 101, 10))


@dataclass(frozen=True)
class Reading:
    """One reading of the paper: its ``key`` (``claims.csv``) and one-line ``title``; the
    evaluation ``thixotropy``, ``clock`` and ``acceleration`` (ODE only) of eqs. (3)-(5)
    (D6, D15); the stance ``depth`` [m] (D10); the table rows' ``labels`` (E6/E7); the
    morphing foot's ``curl_delay`` [s] (D35); and the ``derivation``: why the paper
    supports it."""

    key: str
    title: str
    thixotropy: str = "quasi-static"
    clock: str = "contact"
    acceleration: bool | None = None
    depth: float = STANCE_DEPTH
    labels: str = "table"
    curl_delay: float = 0.0
    derivation: str = ""

    def __post_init__(self) -> None:
        # validated once, as MudTerrain would
        _, _, kappa = evaluation(self.thixotropy, self.clock, self.acceleration)
        object.__setattr__(self, "acceleration", kappa == 1.0)

    def run_key(self, foot: str, depth: float | None = None) -> tuple[object, ...]:
        """What a gait run of ``foot`` on a given table row depends on (not the labels),
        at stance ``depth`` [m] (default the reading's): equal keys share their runs."""
        delay = self.curl_delay if foot == "morphing" else 0.0
        return (self.thixotropy, self.clock, self.acceleration, depth or self.depth, delay)

    def label(self, row: float) -> float:
        """The water content [-] this reading gives the table row printed as ``row``."""
        return round(row + LABELLINGS[self.labels], 10)

    def row(self, label: float) -> float:
        """The printed table row [-] this reading labels ``label``."""
        return round(label - LABELLINGS[self.labels], 10)

    def mud(self, row: float) -> Mud:
        """The paper's mud of the table row printed as ``row`` [-], under this labelling."""
        return paper_mud(self.label(row), labels=self.labels)

    def terrain(self, row: float) -> MudTerrain:
        """The mud terrain of this reading on the table row printed as ``row`` [-]."""
        return MudTerrain(
            self.mud(row),
            thixotropy=self.thixotropy,
            clock=self.clock,
            acceleration=self.acceleration if self.thixotropy == "ode" else None,
        )


_EVALUATION = (
    "Sec. III-A evaluates the stresses with the closed forms 'considering the quasi-static "
    "condition of the foot motion and neglecting the acceleration term', and the flat-foot "
    "force (12) computes each stress 'by (2), (9) and (10)': eq. (9) "
    "sigma_th = (1 - e^{-t/lambda}) sigma_th,ss at the current rate, eqs. (10)-(11) "
    "sigma_s = (1 - e^{-a (t - t_w)}) sigma_s,ss at the current sealing state."
)
_CLOCK = (
    "Eq. (9) is written in t and eq. (10), beside it, in Delta t = t - t_w, 'the time "
    "moment when the foot retraction begins'; supplementary Sec. I derives (9) from rest "
    "with zero initial conditions at t = 0. So the clock of (9) runs from first contact "
    "and only the suction's clock restarts at t_w."
)
_DEPTH = (
    "The paper gives no stance depth. "
    f"The three fixed feet are h_F = {FOOT_HEIGHT * 1e3:.0f} mm tall (Sec. IV-A) and eqs. "
    "(12)-(14) integrate over a foot that is not buried (the flat foot's walls "
    "z L, z W; the curved feet's theta_c = acos(1 - z/R) <= their rim), so the stance "
    f"stays within h_F: {STANCE_DEPTH * 1e3:.0f} mm, the round depth below it, deeper than "
    "every fixed foot's static sinking under 49 N, as a stepping foot pushed into the mud "
    "would be (decision D10). The claims at every stance of 10-26 mm are in 'The claims "
    "against the stance depth'."
)
_TABLE = (
    "The tables label their rows 25/35/45 %, and the claims are stated at '25 %' "
    "(Figs. 9 and 12 and their text in Sec. IV-B), so the 25 % row is used."
)

#: The readings of the matrix; the first is the headline.
READINGS: tuple[Reading, ...] = (
    Reading(
        "paper",
        "the paper's evaluation: eqs. (9)-(11), clock from first contact, 20 mm, table rows",
        derivation=f"{_EVALUATION} {_CLOCK} {_DEPTH} {_TABLE}",
    ),
    Reading(
        "paper-restart",
        "as 'paper', with the clock of eq. (9) restarted at the retraction",
        clock="retraction",
        derivation=(
            "As 'paper', but eq. (9) read as the solution from rest of each constant-rate "
            "phase: the retraction is a new motion from t_w, as the suction's clock of eq. "
            "(10) is. The paper writes (9) in t, so this is the less literal reading."
        ),
    ),
    Reading(
        "ode",
        "eqs. (3) and (5) integrated, acceleration term dropped as in eq. (9)",
        thixotropy="ode",
        acceleration=False,
        derivation=(
            "Eqs. (3) and (5) are the model; Sec. III-A drops the acceleration term of "
            "f_xi to obtain (9). This integrates the ODEs exactly instead of using their "
            "quasi-static solutions (decision D15), at 20 mm with the table's rows."
        ),
    ),
    Reading(
        "ode-acceleration",
        "eqs. (3) and (5) integrated with the acceleration term (mudrft's ODE default)",
        thixotropy="ode",
        acceleration=True,
        derivation=(
            "Eq. (3) as printed, with the lambda eta_inf gamma-ddot term of f_xi that 'brings "
            "the foot inertial effect into the mud rheological behavior' (Sec. II-B); "
            "mudrft's MudTerrain default (decision D6)."
        ),
    ),
    Reading(
        "paper-30mm",
        "as 'paper', with the former 30 mm stance (the feet buried)",
        depth=0.03,
        derivation=(
            "As 'paper' on mudrft's former gait (decision D10 before the 20 mm stance): the tip "
            "sinks 30 mm, deeper than the 26 mm feet, which the closed forms (12)-(14) do not "
            "describe; shown to isolate the effect of burying the feet."
        ),
    ),
    Reading(
        "paper-text-labels",
        "as 'paper', with the text's water-content labels (the 25 % mud is the middle row)",
        labels="text",
        derivation=(
            "The text says three times that the tests used W = 15/25/35 % (Sec. IV-A: 'from "
            "15 % to 35 %', Table I, Sec. IV-C: 'the intermediate water-content regime "
            "(15~35 %)'; supplementary: '35 % was close to the upper limit'), while Tables "
            "S1-S2 print 25/35/45 % (errata E6/E7). Under the text's labels the paper's "
            "'25 %' is the row printed 35 %."
        ),
    ),
    Reading(
        "paper-curl-50ms",
        "as 'paper', with the morphing foot's pads held spread for 50 ms of the retraction",
        curl_delay=0.05,
        derivation=(
            "The paper says the pads retract 'quickly' as the foot lifts, 'breaking the "
            "sealing of the cavity underneath the foot during retraction' (supplementary Sec. "
            "III-C), and that the morphing foot's suction is 40 % of its resistance (Fig. "
            "11): suction builds before the pads curl, at a time the paper does not give. "
            "The headline lets them curl the moment the retraction begins (decision D35, "
            "pad-curl delay 0); this reading holds them spread for 50 ms. The value was "
            "chosen after the headline's verdicts were seen, to show what the 40 % rests "
            "on; the report's 'pad-curl delay' table gives every delay of 0-100 ms."
        ),
    ),
    Reading(
        "former-defaults",
        "mudrft's former defaults: ODE with the acceleration term, 30 mm stance",
        thixotropy="ode",
        acceleration=True,
        depth=0.03,
        derivation=(
            "mudrft's defaults before it adopted the paper's evaluation and the 20 mm stance "
            "(its issue 13; decisions D6, D10 as they were), evaluated on the same claims and "
            "quantities as every other reading, for comparison."
        ),
    ),
)

#: The headline reading: the paper's own evaluation (chosen from the text, before verdicts).
HEADLINE = READINGS[0]
