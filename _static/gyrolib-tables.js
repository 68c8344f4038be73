/* gyrolib: the ledger reads on a phone (issue 35, item 3).

   The ledger's tables have six columns (verdict, item, printed, reproduced, conditions and
   evidence, where); on a phone they were clipped at the right, behind a sideways scroll.
   Below 720 px (gyrolib-layout.css) each row becomes a card: its cells one under another,
   each headed by its column's name.  This script gives every data cell of the ledger page's
   tables that name (data-label, from the table's own header row), and the table the class
   "gyrolib-cards"; the CSS shows it.  Without the script the tables stay tables.
   tests/test_browser.py (test_the_ledger_reads_on_a_phone_without_sideways_scrolling)
   checks the page at 390 px. */
(function () {
  "use strict";

  function label() {
    var page = document.getElementById("the-reproduction-ledger");
    if (!page) return;
    page.querySelectorAll("table").forEach(function (table) {
      var heads = Array.prototype.map.call(table.querySelectorAll("thead th"),
                                           function (th) { return th.textContent.trim(); });
      if (!heads.length) return;
      table.classList.add("gyrolib-cards");
      table.querySelectorAll("tbody tr").forEach(function (tr) {
        Array.prototype.forEach.call(tr.children, function (cell, i) {
          if (heads[i]) cell.setAttribute("data-label", heads[i]);
        });
      });
    });
  }

  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", label);
  } else {
    label();
  }
})();
