"""A headless Debian Chromium driven by Selenium for the explorer's page tests, and helpers that
find Panel/Bokeh widgets inside their shadow roots by their visible labels."""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from pathlib import Path

CHROMIUM = Path("/usr/bin/chromium")
CHROMEDRIVER = Path("/usr/bin/chromedriver")
CHROMIUM_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync",
                  "--disable-dev-shm-usage")


def missing_browser() -> str:
    """Why no browser test can run here ("" when one can)."""
    for path in (CHROMIUM, CHROMEDRIVER):
        if not path.exists():
            return f"{path} is not installed (apt-get install -y chromium chromium-driver)"
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed (pip install 'diffsense[explore]')"
    return ""


class Browser:
    """Chromium with a fresh profile; ``close()`` quits it and removes the profile."""

    def __init__(self, width: int = 1600, height: int = 1250):
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service

        self.profile = tempfile.mkdtemp(prefix="diffsense-chromium-")
        options = webdriver.ChromeOptions()
        options.binary_location = str(CHROMIUM)
        for flag in CHROMIUM_FLAGS:
            options.add_argument(flag)
        options.add_argument(f"--user-data-dir={self.profile}")
        options.add_argument(f"--window-size={width},{height}")
        self.driver = webdriver.Chrome(service=Service(str(CHROMEDRIVER)), options=options)

    def close(self) -> None:
        try:
            self.driver.quit()
        finally:
            shutil.rmtree(self.profile, ignore_errors=True)

    # every element of the page, inside shadow roots too, matching a CSS selector
    _DEEP = """
    const [selector, text] = arguments;
    const out = [];
    const walk = (root) => {
      root.querySelectorAll(selector).forEach(e => { if (!text || e.textContent.includes(text)) out.push(e); });
      root.querySelectorAll('*').forEach(e => { if (e.shadowRoot) walk(e.shadowRoot); });
    };
    walk(document);
    return out;
    """
    # the element matching `selector` in the shadow root whose label (`label_selector`) reads `text`
    _BESIDE = """
    const [label_selector, text, selector] = arguments;
    let found = null;
    const walk = (root) => {
      if (found) return;
      const label = root.querySelector(label_selector);
      if (label && label.textContent.trim().startsWith(text) && root.querySelector(selector)) {
        found = root.querySelector(selector); return;
      }
      root.querySelectorAll('*').forEach(e => { if (e.shadowRoot) walk(e.shadowRoot); });
    };
    walk(document);
    return found;
    """

    def attributes(self, selector: str, attribute: str) -> list:
        """``attribute`` of every element matching ``selector`` (read in one script, so an
        element the page replaces meanwhile cannot go stale); ``"text"`` reads the text."""
        script = self._DEEP.replace("return out;", "return out.map(e => a === 'text' ? e.textContent : "
                                    "e.getAttribute(a));").replace("const [selector, text] = arguments;",
                                                                   "const [selector, text, a] = arguments;")
        return self.driver.execute_script(script, selector, "", attribute)

    def all(self, selector: str, text: str = ""):
        return self.driver.execute_script(self._DEEP, selector, text)

    def one(self, selector: str, text: str = "", timeout: float = 30.0):
        """The first element matching ``selector`` (containing ``text``), waiting for it."""
        t0 = time.monotonic()
        while True:
            found = self.all(selector, text)
            if found:
                return found[0]
            if time.monotonic() - t0 > timeout:
                raise TimeoutError(f"no element {selector!r} with text {text!r} after {timeout} s")
            time.sleep(0.1)

    def labelled(self, label: str, selector: str, label_selector: str = "label, .bk-slider-title"):
        """The ``selector`` element of the widget labelled ``label``."""
        element = self.driver.execute_script(self._BESIDE, label_selector, label, selector)
        if element is None:
            raise LookupError(f"no widget labelled {label!r} with {selector!r}")
        return element

    def wait_until(self, condition, timeout: float = 30.0, what: str = "condition"):
        t0 = time.monotonic()
        while True:
            value = condition()
            if value:
                return value
            if time.monotonic() - t0 > timeout:
                raise TimeoutError(f"{what} not reached after {timeout} s")
            time.sleep(0.05)

    def screenshot(self, path: Path) -> None:
        """The whole page (not only the window) as a PNG: the viewport is made as tall as the
        page for the capture (Chromium clamps a window to its screen), then restored."""
        path.parent.mkdir(parents=True, exist_ok=True)
        size = self.driver.get_window_size()
        width = self.driver.execute_script("return window.innerWidth")
        height = self.driver.execute_script("return window.innerHeight")
        total = self.driver.execute_script("return document.documentElement.scrollHeight")
        self.driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", {
            "width": int(width), "height": max(int(total), int(height)), "deviceScaleFactor": 1, "mobile": False})
        try:
            time.sleep(0.5)  # let Bokeh lay the charts out for the new viewport
            self.driver.save_screenshot(os.fspath(path))
        finally:
            self.driver.execute_cdp_cmd("Emulation.clearDeviceMetricsOverride", {})
            self.driver.set_window_size(size["width"], size["height"])

    def type_over(self, element, text: str) -> None:
        """Replace the text of a text box by ``text`` and press Enter."""
        from selenium.webdriver.common.action_chains import ActionChains
        from selenium.webdriver.common.keys import Keys

        (ActionChains(self.driver).click(element).key_down(Keys.CONTROL).send_keys("a").key_up(Keys.CONTROL)
         .send_keys(text, Keys.ENTER).perform())

    # arm a timer: the next keydown on arguments[0] starts it; the first DOM change of the
    # element matching arguments[1] (found inside shadow roots) whose data-value differs stops it
    _ARM = """
    const [target, selector] = arguments;
    const find = (root) => {
      let hit = root.querySelector(selector);
      if (hit) return hit;
      for (const e of root.querySelectorAll('*')) {
        if (e.shadowRoot && (hit = find(e.shadowRoot))) return hit;
      }
      return null;
    };
    const shown = find(document);
    const root = shown.getRootNode();
    const before = shown.getAttribute('data-value');
    const timer = window.__dsTimer = {start: null, stop: null, value: null};
    target.addEventListener('keydown', () => { if (timer.start === null) timer.start = performance.now(); },
                            {capture: true, once: true});
    const observer = new MutationObserver(() => {
      const now = root.querySelector(selector);
      if (timer.start !== null && now && now.getAttribute('data-value') !== before) {
        timer.stop = performance.now(); timer.value = now.getAttribute('data-value'); observer.disconnect();
      }
    });
    observer.observe(root, {subtree: true, childList: true, attributes: true, characterData: true});
    """
    _READ = """
    const done = arguments[arguments.length - 1];
    const poll = () => { const t = window.__dsTimer;
      if (t.stop !== null) done([t.stop - t.start, t.value]); else setTimeout(poll, 5); };
    poll();
    """

    def timed_key(self, element, key, shown_selector: str, timeout: float = 30.0):
        """Press ``key`` on ``element`` and measure in the page the time (ms) from the key
        press to the change of the ``data-value`` of the element matching ``shown_selector``;
        returns (ms, new data-value)."""
        self.driver.execute_script(self._ARM, element, shown_selector)
        self.driver.set_script_timeout(timeout)
        element.send_keys(key)
        ms, value = self.driver.execute_async_script(self._READ)
        return ms, value
