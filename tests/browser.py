"""A headless Chromium for tests that look at pages as a person does (Playwright).

Debian's ``/usr/bin/chromium`` (CI installs it), driven by Playwright for Python;
no browser is downloaded. Tests using :func:`browser_page` skip with the reason
when either is missing. Screenshots go to ``$MACHDYN_SCREENSHOTS`` or
``tests/screenshots/`` (gitignored) so that a person can look at them.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

CHROMIUM = os.environ.get("MACHDYN_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]


def screenshots() -> Path:
    """The folder screenshots are written to (made if missing)."""
    folder = Path(os.environ.get("MACHDYN_SCREENSHOTS") or Path(__file__).parent / "screenshots")
    folder.mkdir(parents=True, exist_ok=True)
    return folder


@contextmanager
def chromium() -> Iterator[object]:
    """A launched headless Chromium (one per test module: start it in a module fixture)."""
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
    if not Path(CHROMIUM).exists():
        pytest.skip(f"no chromium at {CHROMIUM} (apt-get install chromium)")
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        try:
            yield browser
        finally:
            browser.close()


class Page:
    """A browser tab that records console errors, uncaught exceptions and network requests."""

    def __init__(self, browser: object, width: int = 1000, height: int = 900) -> None:
        self.page = browser.new_page(viewport={"width": width, "height": height})
        self.errors: list[str] = []
        self.requests: list[str] = []
        self.dialogs: list[str] = []
        self.page.on("console", lambda m: self.errors.append(m.text) if m.type == "error" else None)
        self.page.on("pageerror", lambda e: self.errors.append(str(e)))
        self.page.on("request", lambda r: self.requests.append(r.url))

        def dialog(d: object) -> None:
            self.dialogs.append(d.message)
            d.dismiss()

        self.page.on("dialog", dialog)

    def open(self, path: Path, wait_ms: int = 300) -> object:
        self.page.goto(path.resolve().as_uri())
        self.page.wait_for_timeout(wait_ms)
        return self.page

    def shot(self, name: str, full_page: bool = True) -> Path:
        out = screenshots() / f"{name}.png"
        self.page.screenshot(path=str(out), full_page=full_page)
        return out

    def close(self) -> None:
        self.page.close()

    def assert_clean(self, path: Path) -> None:
        """No console error, no uncaught exception, no dialog, nothing but the file loaded."""
        assert not self.errors, self.errors
        assert not self.dialogs, self.dialogs
        others = [u for u in self.requests if u != path.resolve().as_uri()]
        assert not others, others
