import numpy as np

from catwalk.cloth.builder import Panel, Seam, build_cloth, rectangle
from catwalk.simulate.garment_cloth import seam_gaps, weld


def _two_panels():
    a = Panel(rectangle(0.2, 0.3), name="a")
    b = Panel(rectangle(0.2, 0.3), name="b",
              placement=np.array([[1.0, 0, 0, 0.25], [0, 1.0, 0, 0], [0, 0, 1.0, 0]]))
    # a's right edge (vertex 1 → 2) to b's left edge (vertex 3 → 0)
    return build_cloth([a, b], [Seam(0, 1, 2, 1, 3, 0, reverse=True)], h=0.05)


def test_weld_merges_partners_and_keeps_mass():
    m = _two_panels()
    w, rep = weld(m)
    pairs = len(m.seam_a)
    assert pairs >= 7
    assert w.n_points == m.n_points - pairs
    assert np.all(rep[m.seam_a] == rep[m.seam_b])
    assert np.isclose(w.mass.sum(), m.mass.sum())
    assert np.all(w.spring_a != w.spring_b)
    key = np.minimum(w.spring_a, w.spring_b) * w.n_points + np.maximum(w.spring_a, w.spring_b)
    assert len(np.unique(key)) == len(key)          # the two sides' seam springs became one
    assert len(w.seam_a) == 0
    # the welded particle sits between its two points, the cloth is now one piece
    assert np.allclose(w.rest_positions[rep[m.seam_a]],
                       0.5 * (m.rest_positions[m.seam_a] + m.rest_positions[m.seam_b]))
    assert seam_gaps(m, m.rest_positions).max() > 0.04


def test_weld_only_selected_pairs():
    m = _two_panels()
    sel = np.zeros(len(m.seam_a), bool)
    sel[:3] = True
    w, rep = weld(m, sel)
    assert w.n_points == m.n_points - 3
    assert len(w.seam_a) == len(m.seam_a) - 3
    assert np.all(w.seam_a == rep[m.seam_a[~sel]])


def test_no_spring_spans_a_dart():
    # a 30 × 30 cm panel with a 6 cm wide, 12 cm deep dart cut into its top edge
    outline = np.array([[0, 0], [0.3, 0], [0.3, 0.3], [0.18, 0.3], [0.15, 0.18], [0.12, 0.3],
                        [0, 0.3]], float)
    m = build_cloth([Panel(outline, name="p")], [Seam(0, 3, 4, 0, 4, 5, reverse=True)],
                    h=0.02)
    legs_a = set(m.seam_a.tolist()) - set(m.seam_b.tolist())
    legs_b = set(m.seam_b.tolist()) - set(m.seam_a.tolist())
    across = [(a, b) for a, b in zip(m.spring_a.tolist(), m.spring_b.tolist(), strict=True)
              if (a in legs_a and b in legs_b) or (a in legs_b and b in legs_a)]
    assert legs_a and legs_b
    assert across == []
