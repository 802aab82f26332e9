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
  // MathJax 4 breaks a long formula at the width its box had when the page was typeset; when
  // the window's width changes (a window narrowed, a tablet turned), the formulas are laid out
  // again for the new width (MathJax re-measures from its METRICS state: no TeX is parsed
  // again). window.fcMathSettled() resolves when the last such layout is done (the browser
  // check waits for it after it resizes the window).
  var settled = Promise.resolve(), timer = null, lastWidth = window.innerWidth;
  function rebreak() {
    var mj = window.MathJax;
    if (!(mj && mj.startup && mj.startup.document && mj._ && mj._.core)) return Promise.resolve();
    return mj.startup.promise.then(function () {
      return mj.startup.document.rerenderPromise(mj._.core.MathItem.STATE.METRICS);
    });
  }
  window.addEventListener("resize", function () {
    if (window.innerWidth === lastWidth) { mark(); return; }
    lastWidth = window.innerWidth;
    clearTimeout(timer);
    settled = new Promise(function (done) {
      timer = setTimeout(function () { rebreak().then(mark).then(done, done); }, 150);
    });
  });
  window.fcMathSettled = function () { return settled; };
  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", start);
  } else {
    start();
  }
})();
