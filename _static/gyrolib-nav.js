/* gyrolib: the sidebar buttons work at every width (issue 35, item 2).

   The bug.  pydata-sphinx-theme 0.17 (under sphinx-book-theme 1.3) renders two ☰ buttons
   with the class "primary-toggle" (and two "secondary-toggle"): one in the top header,
   which sphinx-book-theme hides, and the visible one in the article header.  Both themes'
   scripts bind document.querySelector(".primary-toggle"), the first, hidden one; the
   visible buttons do nothing: below 992 px neither the navigation nor the contents panel
   opens, and at 992 px and wider ☰ does not collapse the sidebar.  Reported upstream:
     https://github.com/pydata/pydata-sphinx-theme/issues/2451
     https://github.com/executablebooks/sphinx-book-theme/issues/988 (and #935; fix
     proposed in executablebooks/sphinx-book-theme#1000, not in a release that runs under
     Jupyter Book 1's Sphinx).
   Remove this file when the pinned themes bind every toggle.

   The shim binds every toggle button itself, in the capture phase, and stops the themes'
   own handlers on it, so that each click is handled once:
   * ☰ at 992 px and wider collapses and restores the primary sidebar (the class
     sphinx-book-theme uses, "pst-sidebar-hidden"), and says so in aria-expanded;
   * ☰ and the contents button below that width (the contents button is shown below 1200 px)
     move the sidebar's content into the theme's modal <dialog> and open it, as
     pydata-sphinx-theme does for its own button; Escape, a click on the backdrop, or a
     second click close it; the content goes back, focus returns to the button, and
     aria-expanded is "false" again.
   tests/test_browser.py (test_navigation_*) clicks the buttons at 390, 800 and 1280 px. */
(function () {
  "use strict";
  var WIDE = "(min-width: 992px)";

  // pydata-sphinx-theme's own move: the sidebar's children and classes go into the dialog,
  // and back when it closes
  function move(from, to) {
    Array.from(from.childNodes).forEach(function (node) { to.appendChild(node); });
    Array.from(from.classList).forEach(function (cls) {
      from.classList.remove(cls);
      to.classList.add(cls);
    });
  }

  function setExpanded(buttons, value) {
    buttons.forEach(function (b) { b.setAttribute("aria-expanded", value ? "true" : "false"); });
  }

  function bind(selector, sidebar, dialog, collapsible) {
    var buttons = Array.from(document.querySelectorAll(selector));
    if (!buttons.length || !sidebar || !dialog) { return; }
    var opener = null;
    buttons.forEach(function (b) {
      b.setAttribute("aria-controls", sidebar.id);
      b.setAttribute("aria-haspopup", "dialog");
    });
    function expandedNow() {
      if (dialog.open) { return true; }
      if (collapsible && window.matchMedia(WIDE).matches) {
        return !sidebar.classList.contains("pst-sidebar-hidden");
      }
      return false;
    }
    function close() {
      if (dialog.open) { dialog.close(); }
    }
    dialog.addEventListener("close", function () {
      if (dialog.childNodes.length) { move(dialog, sidebar); }
      setExpanded(buttons, expandedNow());
      if (opener && opener.focus) { opener.focus(); }
      opener = null;
    });
    dialog.addEventListener("keydown", function (event) {
      if (event.key === "Escape") {
        event.preventDefault();
        event.stopPropagation();
        close();
      }
    });
    dialog.addEventListener("click", function (event) {  // the backdrop: outside the panel
      var r = dialog.getBoundingClientRect();
      if (event.clientX < r.left || event.clientX > r.right || event.clientY < r.top ||
          event.clientY > r.bottom) {
        close();
      }
    });
    buttons.forEach(function (button) {
      button.addEventListener("click", function (event) {
        event.preventDefault();
        event.stopImmediatePropagation();
        if (collapsible && window.matchMedia(WIDE).matches) {
          sidebar.classList.toggle("pst-sidebar-hidden");
        } else if (dialog.open) {
          close();
        } else {
          opener = button;
          move(sidebar, dialog);
          dialog.showModal();
        }
        setExpanded(buttons, expandedNow());
      }, true);
    });
    setExpanded(buttons, expandedNow());
    window.addEventListener("resize", function () { setExpanded(buttons, expandedNow()); });
  }

  function setup() {
    bind(".primary-toggle", document.getElementById("pst-primary-sidebar"),
         document.getElementById("pst-primary-sidebar-modal"), true);
    bind(".secondary-toggle", document.getElementById("pst-secondary-sidebar"),
         document.getElementById("pst-secondary-sidebar-modal"), false);
  }

  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", setup);
  } else {
    setup();
  }
})();
