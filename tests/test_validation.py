"""Validation report frame: verdicts from conditions, the model registry, the HTML table."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from craquelure import validation
from craquelure.validation import Claim, verdict_of


def test_verdict_from_conditions_names_the_failures():
    assert verdict_of({"a": True, "b": True}) == ("reproduced", "")
    assert verdict_of({"a": True, "b": False}) == ("partly", "fails: b")
    assert verdict_of({"a": False, "b": False}) == ("not reproduced", "fails: a, b")
    assert verdict_of({"a": True, "b": False}, partial=False) == ("not reproduced", "fails: b")
    with pytest.raises(ValueError, match="at least one condition"):
        verdict_of({})


def test_a_sample_that_cannot_decide_gives_inconclusive_never_reproduced():
    verdict, note = verdict_of({"a": True}, {"power 0.3 < 0.8": "about 40 seeds"})
    assert verdict == "inconclusive"
    assert note == "sample cannot decide: power 0.3 < 0.8 (needs about 40 seeds)"
    # A failure still decides, and the note keeps what could not be decided.
    verdict, note = verdict_of({"a": False}, {"b": "100 samples"})
    assert verdict == "not reproduced" and "fails: a" in note and "needs 100 samples" in note
    assert verdict_of({}, {"no fragments": "a longer run"})[0] == "inconclusive"


def test_fraction_decision_is_exact_binomial():
    from craquelure.validation import fraction_decision

    # 3 of 3 seeds: the 95 % interval [0.29, 1] straddles 0.6: undecided, and the note
    # names the sample at the same fraction that would decide (8 of 8: lower bound 0.63).
    decided, need = fraction_decision(3, 3, 0.6)
    assert decided is None and "about 8 samples" in need
    assert fraction_decision(20, 20, 0.6) == (True, "")
    assert fraction_decision(0, 20, 0.6) == (False, "")


def test_claim_rejects_an_unknown_verdict():
    with pytest.raises(ValueError, match="allowed values: reproduced, partly, not reproduced, "
                                         "inconclusive"):
        Claim("drying", "c", "s", "k", "m", "maybe")


def test_collect_rejects_an_unknown_model():
    with pytest.raises(ValueError, match="unknown model.*allowed values: drying, impact"):
        validation.collect({"fluid": ["x.json"]})


def test_outputs_count_and_escape(tmp_path):
    claims = [Claim("impact", "a < b & c", "s", "k", "1", "reproduced"),
              Claim("impact", "d", "s", "k", "2", "partly", "fails: x"),
              Claim("softdyn", "e", "s", "k", "3", "not reproduced", "fails: y"),
              Claim("drying", "f", "s", "k", "4", "inconclusive", "sample cannot decide: z")]
    validation.write_json(claims, tmp_path / "v.json", "ci")
    doc = json.loads((tmp_path / "v.json").read_text())
    assert doc["tally"]["all"] == {"reproduced": 1, "partly": 1, "not reproduced": 1,
                                   "inconclusive": 1}
    assert doc["tally"]["impact"]["partly"] == 1 and len(doc["claims"]) == 4
    assert "git_commit" in doc["provenance"] and "version_numpy" in doc["provenance"]
    html = validation.render_html(claims, "ci")
    assert "a &lt; b &amp; c" in html and "a < b" not in html
    assert "impact: 1 reproduced, 1 partly, 0 not reproduced, 0 inconclusive" in html
    # one badge per claim plus the tally's legend of the four verdicts
    assert html.count('class="cq-badge inconclusive"') == 1 + 1
    assert html.count('class="cq-badge not-reproduced"') == 1 + 1


def test_fraction_power_by_simulation_matches_the_binomial():
    """Power of the exact-interval test of 'fraction >= 1/2' at n samples against a true
    fraction 0.9: it decides when the interval's lower bound clears 1/2 (k = n at n = 8,
    k >= 9 at n = 10), so the power is P(k = 8) = 0.430 and P(k >= 9) = 0.736 within the
    simulation's noise (4000 draws: sd 0.008); 3 samples never decide."""
    from craquelure.validation import fraction_power, samples_for_power

    assert abs(fraction_power(8, 0.9, 0.5) - 0.9**8) < 0.03
    assert abs(fraction_power(10, 0.9, 0.5) - (0.9**10 + 10 * 0.9**9 * 0.1)) < 0.03
    assert fraction_power(3, 0.9, 0.5) == 0.0
    assert samples_for_power(3, 0.9, 0.5) == 12


def _figures(tmp_path, names):
    """Small real PNG figures under results/<model>/... (as the workflow writes them)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = []
    for i, name in enumerate(names):
        path = tmp_path / "results" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
        ax.plot(range(10), [j * (i + 1) for j in range(10)])
        fig.savefig(path)
        plt.close(fig)
        paths.append(path)
    return paths


def _default_like_claims():
    """33 claims as the default profile has them (drying 4, impact 15, lattice 7, softdyn 7),
    with long measured strings, each naming its deciding figure."""
    long = "; ".join(f"quantity {i} = {i * 0.123:.3f} (95 % CI {i * 0.1:.2f}-{i * 0.2:.2f})"
                     for i in range(30))
    spec = {"drying": (4, "drying/figures/drying_inverse_mean_area.png"),
            "impact": (15, "impact/figures/impact_precracks.png"),
            "lattice": (7, "lattice/glen/glen.png"),
            "softdyn": (7, "softdyn/t1_single/fig4.png")}
    claims = []
    for model, (n, figure) in spec.items():
        for i in range(n):
            verdict = validation.VERDICTS[i % 4]
            claims.append(Claim(model, f"{model} claim {i}: " + "a long statement " * 8, "paper",
                                "criterion " * 30, long, verdict, "note " * 20,
                                deciding=f"x = {i}.00 (bound 1)", figure=Path(figure).name))
    return claims, [f for _, f in spec.values()]


def test_summary_rows_fold_the_long_strings_and_embed_the_deciding_figure(tmp_path):
    claims, names = _default_like_claims()
    figures = _figures(tmp_path, names)
    html = validation.render_html(claims, "default", figures)
    # one row per claim, the long strings inside its <details>, badges and numbers outside
    assert html.count('<tr class="cq-row"') == len(claims)
    assert html.count("<details>") == len(claims)
    row = html.split('<tr class="cq-row"')[1]
    summary_part, folded = row.split("</summary>", 1)
    assert "quantity 29" not in summary_part and "quantity 29" in folded
    assert "criterion criterion" in folded and 'class="cq-badge reproduced"' in row
    assert "x = 0.00 (bound 1)" in row
    # each figure embedded once however many claims it decides (background of a class)
    assert html.count("data:image/png;base64,") == len(figures)
    assert validation.figure_for(claims[0], figures) == figures[0]
    # a figure of another model with the same name is never taken
    other = Claim("lattice", "c", "s", "k", "m", "reproduced",
                  figure="drying_inverse_mean_area.png")
    assert validation.figure_for(other, figures) is None
    # the fragment for the report is the same summary
    assert validation.render_summary(claims, "default", figures) in html


def test_validation_page_shows_summary_and_thumbnails_on_the_first_screen(tmp_path):
    """In a real browser at 1280 x 800: the 33 rows of a default-like profile (two columns),
    each with its badge and the thumbnail of its decoded figure, all on the first screen,
    every details element folded."""
    from tests.chromium import first_screen, on_screen, require_chromium

    require_chromium()
    claims, names = _default_like_claims()
    page = validation.write_html(claims, tmp_path / "validation.html", "default",
                                 _figures(tmp_path, names))
    seen = first_screen(page)
    assert seen["found"]
    assert seen["viewport"] == [1280, 800]
    assert len(seen["tables"]) == 2 and all(on_screen(t) for t in seen["tables"])
    assert len(seen["rows"]) == len(claims) and all(on_screen(r) for r in seen["rows"])
    assert all(on_screen(b) for b in seen["badges"])
    assert len(seen["thumbs"]) == len(claims)
    assert all(t["figure"] and on_screen(t) for t in seen["thumbs"])
    assert seen["figures_decoded"] and all(seen["figures_decoded"])
    assert seen["details"] == len(claims) and seen["details_open"] == 0
