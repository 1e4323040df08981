"""Fixtures of the browser tests (the helpers are in browser_helpers.py)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from browser_helpers import chromium, server_log_tails


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    # per module, not per session: the sync API holds an event loop in this thread while Chromium runs, and
    # the server tests after a browser module on the same test process use asyncio.run
    with chromium() as b:
        yield b


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Any:
    """A failing browser test's report ends with its servers' logs: a slow or failed request is found there."""
    report = yield
    if report.failed:
        tails = server_log_tails()
        if tails:
            report.sections.append(("server log", tails))
        browser = getattr(item, "funcargs", {}).get("browser")
        if browser is not None and call.when == "call":
            report.sections.append(("pages", shown_pages(browser)))
    return report


def shown_pages(browser: Any) -> str:
    """Each open page's address and the start of its text, as the browser shows it now."""
    out = []
    for context in browser.contexts:
        for page in context.pages:
            try:
                text = page.inner_text("body", timeout=3000)
            except Exception as err:  # noqa: BLE001 (a page that hangs or is gone says so)
                text = f"({type(err).__name__})"
            out.append(f"--- {page.url}\n{' '.join(text.split())[:600]}")
    return "\n".join(out)
