"""gyrolib.book.report: the number and table formats of the book's prose."""

import numpy as np
import pytest

from gyrolib.book import report
from gyrolib.book.ledger import LedgerItem, format_value


@pytest.mark.parametrize(("x", "digits", "text"), [
    (1.704e-4, 3, "1.70·10⁻⁴"),
    (6.9214e-3, 3, "6.92·10⁻³"),
    (2.36e-15, 2, "2.4·10⁻¹⁵"),
    (12346.0, 4, "1.235·10⁴"),
    (-3.0e7, 1, "-3·10⁷"),
])
def test_sci_writes_superscript_exponents(x, digits, text):
    assert report.sci(x, digits) == text


def test_sci_accepts_numpy_scalars_and_0d_arrays():
    assert report.sci(np.float64(1.704e-4)) == report.sci(np.array(1.704e-4)) == "1.70·10⁻⁴"


@pytest.mark.parametrize(("x", "digits", "text"), [
    (13309.4, 4, "13\u2009310"),
    (106474.2, 3, "106\u2009000"),
    (61.62, 4, "61.62"),
    (0.0339, 3, "0.0339"),
])
def test_grouped_rounds_then_groups_thousands(x, digits, text):
    assert report.grouped(x, digits) == text


@pytest.mark.parametrize("x,bound,text", [(1.4e-15, 1e-14, "below 10⁻¹⁴"),
                                           (-1.6e-15, 1e-14, "below 10⁻¹⁴"),
                                           (0.0, 5e-13, "below 5·10⁻¹³")])
def test_below_cites_the_declared_bound_the_same_on_every_machine(x, bound, text):
    assert report.below(x, bound) == text


@pytest.mark.parametrize("x,message", [(1e-14, "agreement must be below 1e-14"),
                                       (-2e-14, "agreement must be below 1e-14"),
                                       (float("nan"), "agreement")])
def test_below_refuses_a_value_at_or_above_its_bound_by_name(x, message):
    with pytest.raises(ValueError, match=message):
        report.below(x, 1e-14, "agreement")


def test_format_number_takes_a_spec_or_a_function():
    assert report.format_number(np.float64(0.001374), ".5f") == "0.00137"
    assert report.format_number(1.704e-4, report.sci) == "1.70·10⁻⁴"


def test_markdown_table_is_displayed_as_markdown():
    table = report.markdown_table(("t (s)", "Δγ (°)"), [(10, 21.6), (60, 129.6)])
    assert table == "| t (s) | Δγ (°) |\n| --- | --- |\n| 10 | 21.6 |\n| 60 | 129.6 |"
    assert table._repr_markdown_() == str(table)


def test_gluer_prefixes_the_key_and_formats_the_value(monkeypatch):
    glued = {}
    import myst_nb

    monkeypatch.setattr(myst_nb, "glue", lambda key, value, display: glued.update({key: value}))
    gl = report.gluer("gcm_", ".3g")
    gl("rot", np.float64(0.49273))
    gl("dk", 1.704e-4, report.sci)
    assert glued == {"gcm_rot": "0.493", "gcm_dk": "1.70·10⁻⁴"}


def test_ledger_format_value_and_link_target():
    assert format_value(0.00137412) == "0.001374"
    assert format_value(None) == "—" and format_value("figure") == "figure"
    item = LedgerItem(id="gc.x", paper="GC", location="Fig. 3", quantity="q", unit="1",
                      paper_value=1.0, reproduced_value=1.0, status="reproduced", note="n",
                      chapter="chapters/gc_filter", kind="printed number", evidence="e")
    assert item.target == "gc-filter"
    assert LedgerItem(**{**item.__dict__, "anchor": "gc-filter-fig3"}).target == "gc-filter-fig3"
