"""The explorable figures (book/_ext/explorable.py): every slider moved by the keyboard.

:func:`check_explorables` focuses each slider of a loaded page, presses an arrow key, and
checks that the figure, the value and the caption's numbers change to those of the next frame
(which loads), that the slider has a label and shows its focus.
"""

from __future__ import annotations

from .result import PageResult

_EXPLORE_STATE_JS = r"""
(i) => {
  const box = document.querySelectorAll('.fc-explore')[i];
  const img = box.querySelector('img.fc-explore-frame');
  const input = box.querySelector('input.fc-explore-slider');
  const fig = box.closest('figure') || box;
  const label = document.querySelector(`label[for="${input.id}"]`);
  return {src: img.getAttribute('src'), alt: img.alt, loaded: img.complete && img.naturalWidth > 0,
          value: box.querySelector('output.fc-explore-value').textContent,
          valuetext: input.getAttribute('aria-valuetext') || '',
          facts: Array.from(fig.querySelectorAll('.fc-explore-fact')).map(s => s.textContent),
          at: Number(input.value), max: Number(input.max), ready: box.classList.contains(
            'fc-explore-ready'), label: label ? label.textContent.trim() : '',
          focused: document.activeElement === input,
          outline: document.activeElement === input ? getComputedStyle(input).outlineStyle : ''};
}
"""


def check_explorables(page, res: PageResult) -> None:
    """Focus every slider, press an arrow key, and see the figure, the value and the caption's
    numbers change to those of the next frame (which loads), with the focus visible."""
    n = page.evaluate("() => document.querySelectorAll('.fc-explore').length")
    res.explorables = n
    for i in range(n):
        where = f"page {res.path}: explorable figure {i + 1}"
        before = page.evaluate(_EXPLORE_STATE_JS, i)
        if not before["ready"]:
            res.problems.append(f"{where}: its script did not start (explorable.js)")
            continue
        if not before["label"]:
            res.problems.append(f"{where}: the slider has no label for a screen reader")
        key = "ArrowRight" if before["at"] < before["max"] else "ArrowLeft"
        page.locator("input.fc-explore-slider").nth(i).focus()
        page.keyboard.press(key)
        try:
            page.wait_for_function(
                "(i) => { const img = document.querySelectorAll('.fc-explore')[i]"
                ".querySelector('img.fc-explore-frame'); "
                "return img.complete && img.naturalWidth > 0; }", arg=i, timeout=5_000)
        except Exception:  # the next frame did not load: reported below
            pass
        after = page.evaluate(_EXPLORE_STATE_JS, i)
        changed = [k for k in ("src", "alt", "value", "valuetext") if after[k] != before[k]]
        if len(changed) < 4:
            res.problems.append(f"{where}: {key} did not move it (unchanged: "
                                f"{sorted({'src', 'alt', 'value', 'valuetext'} - set(changed))})")
        elif not after["loaded"]:
            res.problems.append(f"{where}: the next frame did not load ({after['src']})")
        elif before["facts"] and after["facts"] == before["facts"]:
            res.problems.append(f"{where}: the caption's numbers did not follow the slider")
        elif not after["focused"] or after["outline"] in ("", "none"):
            res.problems.append(f"{where}: the focused slider shows no visible focus")
        else:
            res.explorables_moved += 1
        page.keyboard.press("ArrowLeft" if key == "ArrowRight" else "ArrowRight")


# ---------------------------------------------------------------- registry figures (helper
# "figures"): every {registry-figure} of book/_ext/registry_figure.py, measured at 1280 px.
