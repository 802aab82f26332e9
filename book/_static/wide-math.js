// Inline formulas wider than their whole line (on a phone: MathJax 4 breaks inline math at
// operators, but a formula without a break point, a long subscript or a matrix, can still be
// wider than the column) get the class fc-wide-math, which makes them scroll sideways in their own box
// (book/_static/fusioncenter.css) instead of running out of the text column. Measured after
// MathJax has typeset the page and again whenever the window changes size; at 1280 px no
// formula of the book needs it (tools/browser_check fails on one that does).
(function () {
  "use strict";
  var SELECTOR = "article.bd-article mjx-container:not([display='true'])";
  function lineWidth(el) {
    var block = el.parentElement;
    while (block && getComputedStyle(block).display.indexOf("inline") === 0) {
      block = block.parentElement;
    }
    if (!block) return Infinity;
    var cs = getComputedStyle(block);
    return block.clientWidth - parseFloat(cs.paddingLeft) - parseFloat(cs.paddingRight);
  }
  function mark() {
    var all = document.querySelectorAll(SELECTOR);
    all.forEach(function (m) { m.classList.remove("fc-wide-math"); });
    all.forEach(function (m) {
      if (m.getBoundingClientRect().width > lineWidth(m) + 0.5) m.classList.add("fc-wide-math");
    });
  }
  function start() {
    var mj = window.MathJax;
    if (mj && mj.startup && mj.startup.promise) {
      mj.startup.promise.then(mark);
    } else if (document.querySelector(".math")) {
      setTimeout(start, 50);  // MathJax is loaded after this script
    }
  }
  window.addEventListener("resize", mark);
  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", start);
  } else {
    start();
  }
})();
