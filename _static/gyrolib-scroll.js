/* gyrolib: a display equation wider than the column scrolls inside its box
   (_static/gyrolib-layout.css).  As the theme does for code blocks and outputs, such a box
   gets a tab stop, so that it can be scrolled from the keyboard (WCAG 2.1.1; axe-core's rule
   scrollable-region-focusable); an equation that fits gets none.  Run when the page has
   loaded, when MathJax has typeset the equations (their width is known only then) and when
   the window is resized. */
(function () {
  "use strict";
  function update() {
    document.querySelectorAll("div.math").forEach(function (el) {
      if (el.scrollWidth > el.clientWidth + 1) {
        el.tabIndex = 0;
      } else {
        el.removeAttribute("tabindex");
      }
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
