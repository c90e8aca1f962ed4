"""Size advice: a garment's sizes against a shopper's girths.

A catalogue garment names, for each size, the sample body it was made for (``fit``: size →
a recipe in ``bodies/recipes.json``); that body's bust, waist and hips are the size's chart.
The chart holds the girths the garment's type covers (a skirt: waist and hips). The ease of a
size is chart − body for each girth (positive: room to spare). A size fits when no
girth is more than ``TIGHT`` smaller than the body's (a garment may stretch that much); the
recommended size is the fitting one with the least room to spare at its loosest girth, or the
largest size when none fits.
"""

from __future__ import annotations

GIRTHS = ("bust", "waist", "hips")
TIGHT = 0.02   # metres a size's chart may fall short of the body's girth and still fit


# the girths a garment of each type covers (a skirt's size has nothing to say about the bust)
COVERS = {"skirt": ("waist", "hips"), "trousers": ("waist", "hips"), "shorts": ("waist", "hips"),
          "tshirt": ("bust", "waist"), "shirt": ("bust", "waist"), "blouse": ("bust", "waist"),
          "top": ("bust", "waist"), "bodice": ("bust", "waist"), "jacket": ("bust", "waist"),
          "coat": ("bust", "waist"), "hoodie": ("bust", "waist")}


def size_chart(garment, recipes: list[dict]) -> dict[str, dict[str, float]]:
    """Size → {girth: metres} from the sample bodies the garment's sizes were made for, the
    girths its type covers only."""
    by_name = {r["name"]: r for r in recipes}
    covers = COVERS.get(garment.type, GIRTHS)
    chart = {}
    for size in garment.sizes:
        recipe = by_name.get(garment.fit.get(size, ""))
        if recipe is not None:
            chart[size] = {k: float(recipe[k]) for k in GIRTHS
                           if k in covers and recipe.get(k) is not None}
    return chart


def advise(garment, body: dict[str, float], recipes: list[dict]) -> dict:
    """``{"recommended", "sizes": [{"size", "chart", "ease", "fits"}], "basis"}``."""
    chart = size_chart(garment, recipes)
    rows = []
    for size in garment.sizes:
        c = chart.get(size)
        if not c:
            rows.append({"size": size, "chart": None, "ease": None, "fits": None})
            continue
        ease = {k: round(c[k] - float(body[k]), 4) for k in c if body.get(k) is not None}
        rows.append({"size": size, "chart": c, "ease": ease,
                     "fits": bool(ease) and min(ease.values()) >= -TIGHT})
    fitting = [r for r in rows if r["fits"]]
    if fitting:
        best = min(fitting, key=lambda r: max(r["ease"].values()))["size"]
    else:
        charted = [r for r in rows if r["chart"]]
        best = charted[-1]["size"] if charted else garment.size(None)
    return {"recommended": best, "sizes": rows,
            "basis": "each size's chart is the sample body it was made for (bodies/"
                     "recipes.json); ease = chart − body; fits: no girth more than "
                     f"{100 * TIGHT:g} cm short"}
