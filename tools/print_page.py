"""A page of the site made ready to print: the print layout and what is read off the page.

:data:`PRINT_CSS` goes on top of the theme's own print CSS (nothing clipped, nothing
collapsed); :data:`NUMBER_JS` puts the chapter's number before its title,
:data:`OPEN_AND_TYPESET_JS` opens every collapsed block and waits for the images and MathJax,
:data:`TARGETS_JS` makes every id a PDF destination and :data:`SECTIONS_JS` reads the chapter's
sections for the bookmarks. Chromium prints the page at :data:`PAGE`; :func:`screen_media`
puts the browser back on screen for the next page. Used by ``tools/pdf_book.py``'s
``Printer``.
"""

from __future__ import annotations

PAGE = {"format": "A4", "margin": {"top": "16mm", "bottom": "18mm", "left": "14mm",
                                   "right": "14mm"}}

# Print styles on top of the theme's own print CSS: nothing clipped, nothing collapsed. They
# apply to the print only (``@media print``). Printer.add emulates print media before Chromium
# prints (the print then needs no layout of its own and none back to the screen: 17 % less
# printing time on four big pages, 8.8 s against 7.3 s, the same pixels on 614 of the fast
# book's 619 pages; of the other five, four change from run to run (the execution status, a
# figure of measured run times) and one code output wraps a full line with a blank line more)
# and leaves the page so: the next page is loaded after :func:`screen_media`, on a blank page,
# where switching back costs nothing (switching back on the printed page itself took 21 s of
# the 76 s that 16 big pages took).
PRINT_CSS = """
@page { size: A4; }
@media print {
html, body { font-size: 10.5pt !important; }
*, *::before, *::after { animation: none !important; transition: none !important;
  box-shadow: none !important; text-shadow: none !important; }
.bd-header, .bd-sidebar-primary, .bd-sidebar-secondary, .bd-header-article, .bd-footer,
.bd-footer-article, .prev-next-area, .header-article-items, .bd-search, #pst-back-to-top,
.headerlink, .toggle-details__summary .tb-icon, .copybtn { display: none !important; }
.bd-main, .bd-content, .bd-article-container, .bd-page-width, .bd-container,
.bd-container__inner, .bd-article { max-width: 100% !important; width: 100% !important;
  padding: 0 !important; margin: 0 !important; overflow: visible !important; }
pre, .highlight pre, .output pre, .cell_output pre, div.highlight {
  white-space: pre-wrap !important; overflow-wrap: anywhere !important;
  word-break: break-word !important; overflow: visible !important; max-height: none !important;
  font-size: 8pt !important; }
.cell_output, .output, .cell_input, div.cell, .table-wrapper, .pst-scrollable-table-container,
.math-wrapper, div.math, mjx-container { overflow: visible !important;
  max-height: none !important; }
mjx-container[display="true"] { max-width: 100% !important; }
table { font-size: 8pt !important; table-layout: auto; }
td, th { word-break: normal !important; overflow-wrap: break-word !important;
  hyphens: auto; }
img { max-width: 100% !important; height: auto !important; page-break-inside: avoid;
      break-inside: avoid; }
/* a figure stays whole with its caption: no image taller than what a page holds beside its
   caption (A4 less the margins is 263 mm), so a tall stacked figure shrinks instead of being
   pushed to the next page (leaving a blank one) and cut there */
figure, .cell_output img { break-inside: avoid !important; page-break-inside: avoid; }
figure img, .cell_output img { max-height: 200mm !important; width: auto !important;
  min-width: 0 !important; margin: 0 auto; display: block; }
figure figcaption { break-before: avoid; }
tr, .admonition-title, .caption { break-inside: avoid; }
h1, h2, h3 { break-after: avoid; }
details > *:not(summary) { display: block !important; opacity: 1 !important; }
details.hide > summary { display: none !important; }
.cell_output img { display: block; margin: 0 auto; }
}
"""

OPEN_AND_TYPESET_JS = """
async () => {
  document.querySelectorAll('details').forEach(d => d.open = true);
  document.querySelectorAll('.toggle-hidden, .toggle-details').forEach(
      e => e.classList.remove('toggle-hidden'));
  const imgs = Array.from(document.images);
  imgs.forEach(i => { if (i.loading === 'lazy') i.loading = 'eager'; });
  await Promise.all(imgs.map(i => i.complete ? null : new Promise(done => {
    i.addEventListener('load', done, {once: true}); i.addEventListener('error', done, {once: true});
    setTimeout(done, 10000); })));
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) {
    await MathJax.startup.promise;
    if (MathJax.typesetPromise) { await MathJax.typesetPromise(); }
  }
  if (document.fonts && document.fonts.ready) { await document.fonts.ready; }
  const h1 = document.querySelector('article h1, main h1, h1');
  let title = document.title;
  if (h1) {  // the title without the chapter number the site puts before it
    const c = h1.cloneNode(true);
    c.querySelectorAll('.section-number, .fc-pdf-number').forEach(e => e.remove());
    title = c.textContent.replace(/[#\\u00b6]/g, '').trim();
  }
  const raw = Array.from(document.querySelectorAll('.math')).filter(el => {
    const c = el.cloneNode(true); c.querySelectorAll('mjx-container').forEach(m => m.remove());
    return /\\$\\$|\\\\\\(|\\\\\\[/.test(c.textContent); }).length;
  return {title: title, rawMath: raw, images: imgs.filter(i => i.naturalWidth > 0).length};
}
"""


# Every element with an id becomes a PDF destination: Chromium writes a named destination for
# each target of a same-page link, so a hidden same-page link to every id makes all of them
# targets (Printer.write turns the links between pages into links inside the PDF).
TARGETS_JS = """
() => {
  const box = document.createElement('div');
  box.style.display = 'none';
  box.className = 'fc-pdf-targets';
  let n = 0;
  for (const el of document.querySelectorAll('article [id], main [id]')) {
    if (!el.id || el.closest('mjx-container, svg')) continue;
    const a = document.createElement('a');
    a.href = '#' + encodeURIComponent(el.id);
    box.appendChild(a);
    n += 1;
  }
  document.body.appendChild(box);
  return n;
}
"""


# The chapter's sections (``<section id=...><h2>``): bookmarks under the chapter's own; and the
# chapter's number before its title (the site numbers figures and exercises by chapter).
SECTIONS_JS = """
() => Array.from(document.querySelectorAll('article section > h2')).map(h => {
  const c = h.cloneNode(true);
  const num = c.querySelector('.section-number');
  const n = num ? num.textContent.trim().replace(/\\.$/, '') : '';
  if (num) num.remove();
  return [h.parentElement.id, n, c.textContent.replace(/[#\\u00b6]/g, '').trim()];
}).filter(s => s[0])
"""
NUMBER_JS = """
(num) => {
  const h1 = document.querySelector('article h1');
  if (h1 && num && !/^\\s*\\d/.test(h1.textContent)) {
    const s = document.createElement('span');
    s.className = 'fc-pdf-number';
    s.textContent = num + '\\u2002';
    h1.prepend(s);
  }
}
"""


def screen_media(page) -> None:
    """A blank page in screen media: what the next page loads into after :meth:`Printer.add`
    left ``page`` in print media."""
    page.goto("about:blank")
    page.emulate_media(media="null")
