// Explorable figures (book/_ext/explorable.py): the slider swaps the frame, its alt text, the
// value beside the slider and the caption's numbers. No network: the frames are the site's.
(function () {
  function setUp(box) {
    var frames = JSON.parse(box.querySelector("script.fc-explore-frames").textContent);
    var img = box.querySelector("img.fc-explore-frame");
    var link = box.querySelector("a.fc-explore-link");
    var input = box.querySelector("input.fc-explore-slider");
    var output = box.querySelector("output.fc-explore-value");
    var figure = box.closest("figure") || box;
    function show(i) {
      var f = frames[i];
      img.src = f.src;
      if (link) link.href = f.src;
      img.alt = f.alt;
      output.textContent = f.value;
      input.setAttribute("aria-valuetext", f.value);
      figure.querySelectorAll(".fc-explore-fact").forEach(function (span) {
        if (span.dataset.fact in f.facts) span.textContent = f.facts[span.dataset.fact];
      });
    }
    input.addEventListener("input", function () { show(Number(input.value)); });
    input.addEventListener("change", function () { show(Number(input.value)); });
    frames.forEach(function (f) { (new Image()).src = f.src; });  // preload: no lag on moving
    box.classList.add("fc-explore-ready");
  }
  function start() { document.querySelectorAll(".fc-explore").forEach(setUp); }
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start);
  else start();
})();
