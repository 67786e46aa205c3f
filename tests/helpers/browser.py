"""Open a report in headless Chromium: did every image and video load, is the verdict there?

The page is copied with a small script appended that, once the page has loaded, records for
every ``<img>`` whether it decoded (``naturalWidth > 0``) and for every ``<video>`` whether its
metadata loaded (or its error code), and whether the verdict box exists; Chromium's
``--dump-dom`` then returns the page with that record in it. The Debian package ``chromium``
provides the browser (``.ci/run`` installs it in CI).
"""

from __future__ import annotations

import json
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome")
_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--allow-file-access-from-files")
_PROBE = """
<script>
window.addEventListener('load', async () => {
  const imgs = [...document.images].map(i => ({src: i.getAttribute('src').slice(0, 60),
                                               ok: i.complete && i.naturalWidth > 0}));
  const vids = await Promise.all([...document.querySelectorAll('video')].map(v =>
    new Promise(done => {
      const seen = () => done({src: v.getAttribute('src'), ok: true, width: v.videoWidth});
      if (v.readyState >= 1) return seen();
      v.addEventListener('loadedmetadata', seen);
      v.addEventListener('error', () => done({src: v.getAttribute('src'), ok: false,
                                               error: v.error && v.error.code}));
      v.load();
    })));
  const out = document.createElement('pre');
  out.id = 'zmpkit-browser-check';
  out.textContent = JSON.stringify({images: imgs, videos: vids,
                                    verdict: document.getElementById('verdict') !== null});
  document.body.appendChild(out);
});
</script>
"""


@dataclass(frozen=True)
class PageCheck:
    """What the browser saw: each image and video, loaded or not, and the verdict box."""

    images: tuple[dict, ...]
    videos: tuple[dict, ...]
    verdict: bool

    @property
    def broken(self) -> list[dict]:
        """Every image or video that did not load."""
        return [e for e in (*self.images, *self.videos) if not e["ok"]]


def chromium() -> str | None:
    """The Chromium executable, or None when none is installed."""
    for name in CHROMIUM_NAMES:
        path = shutil.which(name)
        if path:
            return path
    return None


def check_page(page: Path, browser: str, timeout_s: float = 120.0) -> PageCheck:
    """Load ``page`` (beside its media) with the probe and return what the browser saw."""
    probe = page.with_name(f".{page.stem}.browser-check.html")
    probe.write_text(page.read_text(encoding="utf-8").replace("</body>", _PROBE + "</body>"))
    try:
        dom = subprocess.run(
            [browser, *_FLAGS, "--virtual-time-budget=20000", "--dump-dom", probe.as_uri()],
            capture_output=True, text=True, timeout=timeout_s, check=True,
        ).stdout  # fmt: skip
    finally:
        probe.unlink(missing_ok=True)
    start = dom.index('<pre id="zmpkit-browser-check">') + len('<pre id="zmpkit-browser-check">')
    record = json.loads(_unescape(dom[start : dom.index("</pre>", start)]))
    return PageCheck(tuple(record["images"]), tuple(record["videos"]), record["verdict"])


def screenshot(page: Path, browser: str, path: Path, size: tuple[int, int] = (1280, 900)) -> Path:
    """A PNG of the page's first screen, ``size`` [px] wide and high."""
    subprocess.run(
        [browser, *_FLAGS, f"--window-size={size[0]},{size[1]}", "--hide-scrollbars",
         f"--screenshot={path}", page.as_uri()],
        capture_output=True, timeout=120, check=True,
    )  # fmt: skip
    return path


def _unescape(text: str) -> str:
    return (
        text.replace("&quot;", '"').replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&")
    )
