"""Landa et al. (2020): the testbed run of the reciprocity search and of gradient ascent.

The paper reports one run of each strategy on its testbed: reciprocity 7 readings, 4.35 cm
off; gradient ascent 18 samples, 5 cm off. It reports of the testbed only the sensor's
curve (flat above grey 185) and its noise (σ = 12), both modelled; nothing about the
print's tone, the strength or the wall placement, so no testbed mismatch is set by
default (``--mismatch`` sets one). The truth is its own discretisation (P2, 1.4 cm).

20 runs on the simulated car, means with Student-t 95 % intervals (2026-11-25; the
defaults' column re-run after the planner's reverse sweeps changed order, which moves the
car's value functions by up to 0.17 cm: reciprocity's error was 0.72 [0.37, 1.07], the
rest is unchanged):

========================  =====  ======================  ======================
row                       paper  our defaults            ``--protocol paper``
========================  =====  ======================  ======================
reciprocity readings      7      4.15 [3.98, 4.32]       30.0 [30.0, 30.0]
reciprocity error, cm     4.35   0.83 [0.47, 1.19]       0.26 [0.19, 0.34]
gradient samples          18     20.2 [18.9, 21.5]       28.5 [18.6, 38.3]
gradient error, cm        5      2.04 [1.45, 2.63]       1.45 [1.12, 1.78]
========================  =====  ======================  ======================

Verdicts. Reciprocity under the paper's rules is not reproduced: its estimate is good
(0.26 cm), but its stop never fires within the 30 readings. Eq. (8)'s mean of the maps,
with σ² the noise variance, keeps ``{P_M >= 0.1}`` wider than ``A_eps = 40 cm²``, and the
paper gives no values for ε or A_eps (the preset's are ours). Gradient ascent under the
paper's rule is reproduced in samples: the paper's 18 lies just below our interval, and
one run of the paper's cannot be told apart from our spread. Its error is smaller than
the paper's single run. With our defaults both stop by their own rules, in fewer readings
than the paper's.

The stop's two free values, measured (``benchmarks/landa_paper_stop.yaml``, the paper's
rules on the car, 10 runs per pair; readings mean, success, median error in cm):

==========  ====================  ====================  ====================
ε           A_ε = 40 cm²          200 cm²               1000 cm²
==========  ====================  ====================  ====================
0.1         30.0, 0 %, 0.29       30.0, 0 %, 0.29       30.0, 0 %, 0.29
0.5         28.0, 30 %, 0.33      24.7, 60 %, 0.39      21.6, 90 %, 0.39
0.9         15.6, 80 %, 0.70      14.3, 80 %, 3.1       10.5, 10 %, 11.8
==========  ====================  ====================  ====================

With ε = 0.1 the region holds 16 900 of the arena's 19 600 cm² after 30 readings: eq.
(8)'s mean of the maps barely narrows. No pair gives the paper's 7 readings with a good
estimate; the fewest readings (10.5 at ε = 0.9, A_ε = 1000 cm²) come with 10 % success.
So the paper's 7 readings are not explained by its stop parameters alone. Our product of
the maps (the default) narrows in 4 readings.

**Which testbed imperfection gives the paper's errors?** The paper reports of its testbed
only the sensor's curve and noise, both modelled, and one error per strategy: 4.35 cm
(reciprocity) and 5 cm (gradient), against our 0.7 and 2.0 cm on a matched testbed.
Each imperfection alone, on the car with our defaults (``benchmarks/landa_testbed_mismatch.yaml``,
10 runs per cell; mean error in cm with its Student-t 95 % interval, then readings or
samples; a wall shift of 2 cm makes the paper arena's obstacles overlap, so +1 cm):

=========================  ==========================  ==========================
true world                 reciprocity: error, reads   gradient: error, samples
=========================  ==========================  ==========================
matched                    1.01 [0.29, 1.74], 4.0      2.42 [1.27, 3.56], 18.8
print tone γ 0.7           10.4 [6.4, 14.3], 3.9       2.17 [1.16, 3.19], 19.8
print tone γ 0.85          5.12 [4.27, 5.98], 3.4      1.55 [1.11, 1.99], 19.6
print tone γ 1.2           5.73 [2.96, 8.50], 4.2      2.07 [1.10, 3.04], 16.2
print tone γ 1.5           13.8 [9.8, 17.7], 4.2       2.00 [1.12, 2.88], 16.1
strength × 0.7             9.42 [7.64, 11.19], 4.0     1.78 [0.96, 2.60], 20.3
strength × 0.85            2.87 [1.87, 3.87], 4.0      2.02 [1.36, 2.68], 19.4
strength × 1.2             4.13 [3.46, 4.79], 3.6      3.36 [1.78, 4.94], 20.3
strength × 1.5             6.05 [5.56, 6.55], 3.7      4.87 [3.91, 5.84], 24.3
walls shifted −2 cm        2.19 [1.21, 3.18], 4.0      2.35 [1.57, 3.13], 20.0
walls shifted +1 cm        0.66 [0.39, 0.93], 4.0      1.66 [0.95, 2.38], 19.9
=========================  ==========================  ==========================

The gradient's error is insensitive to everything but a stronger source (it climbs the
true field, whatever its scale); the reciprocity search's error follows every error in
the signal's scale or tone, and the wall placement moves neither. Only a source about
20-50 % stronger than assumed (or, the same to both strategies, a calibration 20-50 % off
in gain) brings both errors to the paper's: at × 1.2 the paper's 4.35 cm lies inside our
interval and its 5 cm at the edge of the gradient's. ``--protocol testbed`` runs the 20-run
table on that testbed (``TESTBED_MISMATCH``). The readings move with none of these (3.4-4.2
against the paper's 7): the paper's seven readings come from its stop rule, not its
testbed (above).

``reproduce landa2020-testbed --protocol testbed`` (20 runs on the car; means with
Student-t 95 % intervals, and where the paper's single run falls among ours):

========================  =====  ======================  =====================================
row                       paper  ``--protocol testbed``  verdict
========================  =====  ======================  =====================================
reciprocity readings      7      3.80 [3.51, 4.09]       not reproduced (the stop rule, above)
reciprocity error, cm     4.35   3.71 [3.19, 4.23]       reproduced: the paper's run is our
                                                         median run (50 % of ours ≥ 4.35)
gradient samples          18     19.9 [19.1, 20.7]       reproduced within 10 %
gradient error, cm        5      2.92 [2.05, 3.78]       plausible: 20 % of our runs ≥ 5 cm
========================  =====  ======================  =====================================
"""

from __future__ import annotations

from ..paper_table import PaperTable, PaperValue, register

__all__ = ["LANDA2020_TESTBED", "PAPER_CAR", "TESTBED_MISMATCH"]

#: The car of ``--protocol paper``, as the paper ran it (section V): the HJ value functions
#: of a bank of targets 12.7 cm apart (the nearest one drives the car), and one raw
#: 30 Hz sample per reading (a dwell of 1/30 s), whose noise is the paper's sigma = 12 ADC
#: counts (see the module doc).
PAPER_CAR = {"planner": "bank", "bank_spacing": 12.7, "dwell": 1 / 30}

#: The testbed imperfection of ``--protocol testbed``: inferred from the paper's two errors
#: (see the module doc), not reported by the paper.
TESTBED_MISMATCH = {"strength_factor": 1.2}

LANDA2020_TESTBED = register(PaperTable(
    name="landa2020-testbed",
    title="reciprocity search vs gradient ascent on the car testbed, from the paper arena's "
          "start to its source",
    reference="Landa et al. (2020), testbed experiment (Sec. 5)",
    build_spec=lambda runs: {"strategies": ["reciprocity", "gradient"], "scenarios": ["paper"],
                             "platform": "car", "seeds": runs},
    paper=(PaperValue("reciprocity", "n_measurements", 7.0),
           PaperValue("reciprocity", "error", 4.35),
           PaperValue("gradient", "n_samples", 18.0),
           PaperValue("gradient", "error", 5.0)),
    default_runs=20,
    note="The paper reports a single run of each strategy (no interval); our runs differ in "
         "the sensor noise and the car's actuation only (same arena, source and start). Our "
         "defaults (not the paper's rules) run here; --protocol paper runs the paper's.",
    protocols={"paper": (
        lambda runs: {"strategies": {"reciprocity": {"preset": "paper"},
                                     "gradient": {"stop_radius": 0, "stall_steps": 0}},
                      "scenarios": ["paper"], "platform": "car", "platform_options": dict(PAPER_CAR),
                      "seeds": runs},
        "Protocol 'paper': both strategies as the paper states them, on the car as the paper ran "
        "it: reciprocity with preset='paper' (step 13's nearest point, eq. (8)'s mean, sigma the "
        "noise of one reading, no extent or tail rule; eps = 0.7, A_eps = 40 cm², d = 12.7 cm are "
        "ours, the paper gives none: benchmarks/landa_paper_preset.md), gradient ascent stopping "
        "at I_max only (stop_radius=0, stall_steps=0); the car plans with the bank of value "
        "functions 12.7 cm apart and reads one raw 30 Hz sample per reading (planner=bank, "
        "dwell=1/30 s). The paper reports one run of each (no interval); ours differ in the "
        "sensor noise and the car's actuation only."),
        "testbed": (
        lambda runs: {"strategies": ["reciprocity", "gradient"], "platform": "car", "seeds": runs,
                      "scenarios": [{"name": "paper", "label": "paper-testbed",
                                     "world": {"mismatch": dict(TESTBED_MISMATCH)}}]},
        "Protocol 'testbed': our defaults on a testbed whose signal is 20 % stronger than the "
        "strategies assume (mismatch strength_factor 1.2, equivalently a sensor calibration "
        "20 % off in gain): of the imperfections swept one at a time "
        "(benchmarks/landa_testbed_mismatch.yaml), the one that brings both strategies' errors "
        "to the paper's (4.35 and 5 cm). Inferred from the paper's two errors, not reported by it.")},
))
