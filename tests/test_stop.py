"""Why a search stopped: :class:`vhfit.calibration.Stop`, a kind for the code and the
sentence users read; a run's interruption, written and read as the results file's
``"status"``; the search space that says whether a method is separable."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import vhfit
from vhfit.calibration import Stop, StopKind, interrupted_in
from vhfit.calibration._checkpoint import load, save
from vhfit.calibration._space import SPACES, FullSpace, SeparableSpace
from vhfit.cli._cards import unfinished

HERE = Path(__file__).resolve().parent

#: The sentences the results files of earlier releases hold, each with what it says.
SENTENCES = {
    "target reached": StopKind.TARGET,
    "target reached by a polish of the best member": StopKind.TARGET_POLISHED,
    "converged": StopKind.CONVERGED,
    "converged: population gathered, ended by a polish of the best member":
        StopKind.GATHERED,
    "mean error improved < 1% over 30 generations": StopKind.STALLED,
    "max_time": StopKind.MAX_TIME,
    "maxiter": StopKind.MAX_ITER,
    "callback": StopKind.CALLBACK,
    "interrupted": StopKind.INTERRUPTED,
    "no finite error in 50 generations": StopKind.NO_FINITE,
    "nothing to search": StopKind.NOTHING,
    "per-decade spectrum (NNLS on a tau grid, pruning, free-tau refinement)":
        StopKind.SPECTRUM,
}


@pytest.mark.parametrize("sentence", SENTENCES)
def test_each_sentence_reads_back_as_its_kind_and_prints_unchanged(sentence):
    stop = Stop.read(sentence)
    assert stop.kind is SENTENCES[sentence]
    assert str(stop) == f"{stop}" == stop.message == sentence


def test_the_stops_a_search_writes_are_the_sentences_of_earlier_releases():
    fixed = {s: k for s, k in SENTENCES.items()
             if k not in (StopKind.STALLED, StopKind.NO_FINITE)}
    assert {Stop.of(k).message: k for k in fixed.values()} == fixed
    assert str(Stop.stalled(0.01, 30)) == "mean error improved < 1% over 30 generations"
    assert str(Stop.no_finite(50)) == "no finite error in 50 generations"
    assert {k for k in StopKind} == {*SENTENCES.values(), StopKind.OTHER}


def test_a_sentence_of_no_kind_is_kept_as_other():
    stop = Stop.read("the solver's own words")
    assert stop.kind is StopKind.OTHER and str(stop) == "the solver's own words"
    assert Stop.read("mean error improved over generations").kind is StopKind.OTHER
    with pytest.raises(KeyError):  # these kinds say more than a fixed sentence
        Stop.of(StopKind.STALLED)


def test_only_an_interrupted_stop_is_interrupted():
    assert [k for k in StopKind if Stop(k, "").interrupted] == [StopKind.INTERRUPTED]


def _cal(stop_reason):
    return vhfit.Calibration(model=vhfit.ViscoHyperelastic("neo_hooke", 0),
                             params=dict(C10=0.5), rmsape=1.0, per_curve_rmsape=[1.0],
                             nit=1, nfev=1, wall_time=0.0, stop_reason=stop_reason)


def test_a_calibration_reads_a_sentence_given_and_writes_it_back(tmp_path):
    cal = _cal("interrupted")
    assert cal.stop_reason == Stop(StopKind.INTERRUPTED, "interrupted") and cal.interrupted
    assert not _cal("maxiter").interrupted
    assert "stop: interrupted" in cal.summary()
    cal.save(tmp_path / "r.json", interrupted=True)
    res = json.loads((tmp_path / "r.json").read_text())
    assert (res["stop_reason"], res["status"], res["interrupted"]) == (
        "interrupted", "interrupted", True)
    back = vhfit.Calibration.load(tmp_path / "r.json")
    assert back.stop_reason == cal.stop_reason and interrupted_in(back.context)
    _cal("maxiter").save(tmp_path / "c.json")
    res = json.loads((tmp_path / "c.json").read_text())
    assert (res["status"], res["interrupted"]) == ("complete", False)


def test_a_results_file_of_format_1_reads_its_stop_and_marks_its_card():
    old = vhfit.Calibration.load(HERE / "data" / "results_v1" / "results.json")
    assert old.stop_reason.kind is StopKind.MAX_ITER and not old.interrupted
    assert unfinished(old).startswith("NOT CONVERGED: the search stopped at maxiter ")
    assert not interrupted_in(old.context)


def test_the_card_marks_only_the_stops_before_convergence():
    marked = {k for k in StopKind if unfinished(_cal(Stop(k, k.value)))}
    assert marked == {StopKind.MAX_TIME, StopKind.MAX_ITER, StopKind.CALLBACK,
                      StopKind.INTERRUPTED}
    assert unfinished(_cal("converged"), interrupted=True).startswith("INTERRUPTED: ")


@pytest.mark.parametrize("record, interrupted", [
    ({"interrupted": True, "status": "interrupted"}, True),
    ({"interrupted": False, "status": "complete"}, False),
    ({"status": "interrupted"}, True),  # the word alone (a record without the flag)
    ({"status": "complete"}, False),
    ({}, False),  # a result built by hand: nothing says it was cut
])
def test_a_records_interruption_is_its_flag_else_its_status_word(record, interrupted):
    assert interrupted_in(record) is interrupted


def test_a_checkpoint_keeps_the_sentence_and_gives_the_kind_back(tmp_path):
    path = tmp_path / "ck.json"
    gathered = Stop.of(StopKind.GATHERED)
    save(path, "key", {"s": 1}, 7, gathered)
    assert json.loads(path.read_text())["done"] == (
        "converged: population gathered, ended by a polish of the best member")
    assert load(path, "key") == ({"s": 1}, 7, gathered)
    save(path, "key", {"s": 1}, 7)
    assert load(path, "key")[2] is None


def test_the_space_of_a_method_says_whether_it_is_separable():
    assert SPACES["separable"] is SeparableSpace and SeparableSpace.separable
    assert SPACES["full"] is FullSpace and not FullSpace.separable
    s = vhfit.CalibrationSettings(method="full")
    assert s.space is FullSpace and s.effective_tol == 1e-5  # the paper's gap
    assert vhfit.CalibrationSettings().space is SeparableSpace


def test_a_stop_equals_its_sentence_as_the_string_it_replaced():
    """A user's ``cal.stop_reason == "maxiter"`` keeps working (and in sets and dicts)."""
    from vhfit.calibration import Stop, StopKind

    stop = Stop.of(StopKind.MAX_ITER)
    assert stop == "maxiter" and "maxiter" == stop and stop != "converged"
    assert stop in {"maxiter"} and {stop: 1}["maxiter"] == 1
    assert stop == Stop.read("maxiter") and stop != Stop.of(StopKind.CONVERGED)
    assert stop != 3
