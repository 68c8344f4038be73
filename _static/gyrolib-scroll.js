/* gyrolib: a display equation or table wider than the column scrolls inside its box
   (_static/gyrolib-layout.css), with a shadow at each edge where its content is cut (the
   classes gyrolib-cut-left/-right, updated as it scrolls).  As the theme does for code
   blocks and outputs, a wide equation's box gets a tab stop, so that it can be scrolled from
   the keyboard (WCAG 2.1.1; axe-core's rule scrollable-region-focusable); an equation that
   fits gets none.  Run when the page has loaded, when MathJax has typeset the equations
   (their width is known only then) and when the window is resized. */
(function () {
  "use strict";
  // A box that scrolls shows where its content is cut: a class per cut edge, which
  // _static/gyrolib-layout.css draws as an inner shadow (tables and equations alike).
  var BOXES = "div.math, .pst-scrollable-table-container, div.table-wrapper";
  function edges(el) {
    var cut = el.scrollWidth > el.clientWidth + 1;
    el.classList.toggle("gyrolib-cut-left", cut && el.scrollLeft > 1);
    el.classList.toggle("gyrolib-cut-right",
                        cut && el.scrollLeft + el.clientWidth < el.scrollWidth - 1);
  }
  function update() {
    document.querySelectorAll("div.math").forEach(function (el) {
      if (el.scrollWidth > el.clientWidth + 1) {
        el.tabIndex = 0;
      } else {
        el.removeAttribute("tabindex");
      }
    });
    document.querySelectorAll(BOXES).forEach(function (el) {
      if (!el.dataset.gyrolibEdges) {
        el.dataset.gyrolibEdges = "1";
        el.addEventListener("scroll", function () { edges(el); }, {passive: true});
      }
      edges(el);
    });
  }
  function afterMathJax(tries) {
    var mj = window.MathJax;
    if (mj && mj.startup && mj.startup.promise) {
      mj.startup.promise.then(update);
    } else if (tries > 0) {
      setTimeout(function () { afterMathJax(tries - 1); }, 100);
    }
  }
  var timer = null;
  window.addEventListener("resize", function () {
    clearTimeout(timer);
    timer = setTimeout(update, 200);
  });
  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", update);
  } else {
    update();
  }
  afterMathJax(300);
})();
