"""The FreeSewing drafts' body lengths, measured on our sample bodies
(``catwalk garment freesewing-lengths`` writes ``garments/freesewing/lengths.json``)."""

from __future__ import annotations

from catwalk.body.measure import measure_body
from catwalk.catalogue.bodies import load_recipes, sample_body

#: FreeSewing measurements (mm) that ``freesewing_lengths`` takes from our sample bodies: the
#: model sets' lengths are not our bodies' (the base female's arm is 47 cm from shoulder to
#: wrist against the models' 59–61 cm; male-L's waist is 1.07 m up against 1.18 m), and the
#: arms and bust points of our bodies do not follow the chest girth as the model sets' do
#: (female-S: upper arm 29.0 cm against the scaled model's 26.3, bust points 21.4 cm apart
#: against 16.0 — the bodice's sleeves and darts would not close on it). ``bustSpan`` is
#: measured on women only.
BODY_LENGTHS = ("waistToFloor", "waistToKnee", "inseam", "shoulderToWrist", "biceps",
                "bustSpan")


def freesewing_lengths(recipes: list[dict] | None = None) -> dict:
    """For every sample body (``bodies/recipes.json``, made once into bodies/generated/):
    the measurements in :data:`BODY_LENGTHS`, in mm, measured on the body as
    ``catwalk body measure`` does (waist, knee and crotch heights above the soles, the arm
    from the shoulder point through the elbow to the wrist, the upper-arm girth, the
    distance between the bust points)."""
    out = {}
    for r in recipes if recipes is not None else load_recipes():
        body = sample_body(r["name"])
        m = measure_body(body.vertices, body.faces, r["sex"])
        lm = m["landmarks"]
        floor = float(body.vertices[:, 1].min())
        knee = 0.5 * (lm["knee_left"][1] + lm["knee_right"][1])
        mm = {"waistToFloor": lm["waist"][1] - floor, "waistToKnee": lm["waist"][1] - knee,
              "inseam": m["inseam"], "shoulderToWrist": m["arm_length"],
              "biceps": m["upper_arm_girth"], "bustSpan": m.get("bust_span")}
        out[r["name"]] = {k: round(1000.0 * float(mm[k]), 1) for k in BODY_LENGTHS
                          if mm[k] is not None}
    return out
