"""Landa et al. (2020): the testbed run of the reciprocity search and of gradient ascent.

The paper reports one run of each strategy on its testbed: reciprocity 7 readings, 4.35 cm
off; gradient ascent 18 samples, 5 cm off. It reports of the testbed only the sensor's
curve (flat above grey 185) and its noise (σ = 12 ADC counts), both modelled; nothing about
the print's tone, the strength or the wall placement, so no testbed mismatch is set by
default (``--mismatch`` sets one). The truth is its own discretisation (P2, 1.4 cm).

**The readings as the paper took them** (``--protocol paper``). The paper's sensor streams
at 30 Hz, and its σ = 12 counts is the noise of those readings; it describes no averaging.
So under ``--protocol paper`` a reading is one raw sample: the car dwells 1/30 s
(:data:`PAPER_CAR`), which through the calibration is 8.4-9.2 signal units of noise per
reading, and the strategy's σ of eq. (7) is that noise (the car states it as the ``noise``
of its readings; the world's point-reading noise does not apply to the car). Our defaults
keep the 1 s dwell, the mean of 30 samples (2.25 units): our choice, not the paper's. The
car plans with the paper's bank of value functions, targets 12.7 cm apart (57 on
``paper``'s free region, where the paper had about 100 on its floor; 25 s to build on one
core, then cached under ``$HJPLANNER_CACHE``).

The three protocols, 20 runs each on the simulated car; means with Student-t 95 %
intervals (2026-11-26, one worker; ``reproduce landa2020-testbed`` prints this table, with
verdicts, once the protocols have run into their default folders side by side):

========================  =====  ===================  ===================  ======================
row                       paper  our defaults         ``--protocol paper`` ``--protocol testbed``
========================  =====  ===================  ===================  ======================
reciprocity readings      7      4.35 [4.12, 4.58]    9.45 [6.22, 12.68]   4.00 [3.57, 4.43]
reciprocity error, cm     4.35   0.51 [0.28, 0.74]    20.4 [8.1, 32.7]     3.50 [3.01, 3.99]
gradient samples          18     20.2 [18.9, 21.5]    51.3 [37.9, 64.7]    19.9 [19.1, 20.7]
gradient error, cm        5      2.04 [1.45, 2.63]    6.40 [-0.37, 13.18]  2.92 [2.05, 3.78]
========================  =====  ===================  ===================  ======================

Verdicts (where the paper's single run falls among our runs):

========================  ===========================  ================================  ==============================
row                       our defaults                 ``--protocol paper``              ``--protocol testbed``
========================  ===========================  ================================  ==============================
reciprocity readings      fewer than the paper's (no   **reproduced**: 7 in our          fewer (none of ours ≥ 7)
                          run of ours ≥ 7)             interval; 19 of 20 stop by
                                                       the rule
reciprocity error, cm     smaller (none ≥ 4.35)        **not reproduced**: median        plausible: 40 % of ours
                                                       10.3 cm, 7 of 20 within 5 cm;     ≥ 4.35 (median 3.24 cm)
                                                       the region closes on a wrong
                                                       crossing of level sets in the
                                                       others (one run at the cap)
gradient samples          reproduced within 10 %       **not reproduced**: 51 [38, 65],  reproduced within 10 %
                          (90 % of ours ≥ 18)          every run ≥ 18; the raw
                                                       samples make the 3-sample
                                                       gradient noisy (2 of 20 at the
                                                       60-sample cap)
gradient error, cm        smaller (5 % of ours ≥ 5)    in our interval (median 2.1 cm)   plausible (20 % of ours ≥ 5)
========================  ===========================  ================================  ==============================

So under the paper's rules on the car as the paper ran it, the reciprocity search now
stops by its own rule in the paper's number of readings, but with ε = 0.7 (ours) only
about half of such runs end within 5 cm: the 30-run offline set put 18 of 30 there, this
table's 20 campaign seeds 7 of 20 (pooled 25 of 50, Wilson [37, 63 %]). The paper's
single run at 4.35 cm is one of the good ones. This column was re-run after issue 33 made an
empty region (eq. (8)'s mean below ε everywhere) no longer a stop: it was 7.30 [6.20,
8.40] readings and 23.7 cm then, 20 of 20 stopping. The defaults' and testbed columns were re-run
after the likelihood's error terms and the credible rule (issue 33): reciprocity takes 0.2
more readings under our defaults (4.15 → 4.35) and its error falls (0.78 → 0.51 cm); on the
testbed 3.75 → 4.00 readings, 3.79 → 3.50 cm. The gradient's rows are unchanged.

**The stop's free values** (``benchmarks/landa_paper_preset.md``, made by
``benchmarks/landa_paper_preset.py``): 30 runs of the paper protocol's car recorded to 30
readings, the stop re-evaluated offline over ε from 0.1 to 0.95 and A_ε from 20 to 2000
cm². With eq. (8), ε = 0.1 never stops (0 of 30 within 30 readings): the region ``{P_M
>= 0.1}`` keeps nearly the whole free area (under the former protocol it held 16 900 cm²
after 30 readings: 98 % of ``paper``'s free area of 17 294 cm², the 19 600 cm² floor less
its obstacles). ε = 0.7 with A_ε = 40 cm² stops in 8.7 [7.0, 10.4]
readings with 18 of 30 within 5 cm, the pair nearest the paper's 7; no faithful pair does
better than 21 of 30 (ε = 0.5, A_ε = 500 cm², 12 readings). The smallest deviation that
stops with a good estimate is the product of the same maps (ε = 0.1, A_ε = 20 cm²: 8.7
readings, 25 of 30 within 5 cm), or its 95 % credible region below 20 cm² (8.9 readings,
27 of 30). With the former preset's d = 6 cm the bank snaps every next point back to the
lattice point just read and the car never moves; the preset's d is one bank spacing,
12.7 cm (ours).

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
