"""What students get: JupyterLab started the way ``make lab`` does (as root too), and the student book.

- ``make lab`` runs ``python -m amdo_lab lab``, which passes ``--allow-root`` when the user id is 0
  (Jupyter refuses root otherwise): the test starts it, fetches ``/api`` over HTTP and stops it.
- ``python -m amdo_lab site --student`` builds the book from the release: the test builds it from
  the release of the migrated chapters (``conftest.course_release``), opens chapter 0's page in
  headless Chromium and finds no text of any solution, no folded solution and no hidden test, and
  the download button serves the release notebook (no solution cell, no hidden test).
"""

from __future__ import annotations

import json
import os
import re
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import nbformat
import pytest

from amdo_lab.course.book import build_site
from amdo_lab.chapters import find_chapter
from amdo_lab.course.cells import SOLUTION_TAG, tags

ROOT = Path(__file__).resolve().parents[1]
LAB_START_S = 240


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def test_make_lab_runs_the_lab_command_that_allows_root():
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    recipe = makefile.split("\nlab: ", 1)[1].split("\n\n", 1)[0]
    assert "-m amdo_lab lab" in recipe
    student = makefile.split("\nlab-student: ", 1)[1].split("\n\n", 1)[0]
    assert "-m amdo_lab lab --student" in student


def test_the_lab_serves_over_http_as_this_user_and_stops(tmp_path):
    port, token = _free_port(), "amdo-test"
    env = {**os.environ, "JUPYTER_RUNTIME_DIR": str(tmp_path / "runtime"), "JUPYTER_CONFIG_DIR": str(tmp_path / "cfg")}
    process = subprocess.Popen(
        [sys.executable, "-m", "amdo_lab", "lab", "--no-browser", f"--port={port}", "--ServerApp.ip=127.0.0.1",
         f"--IdentityProvider.token={token}"],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + LAB_START_S
        answer = None
        while time.monotonic() < deadline and process.poll() is None:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/status?token={token}", timeout=5) as reply:
                    answer = (reply.status, json.loads(reply.read().decode()))
                    break
            except OSError:
                time.sleep(1)
        if answer is None:
            process.terminate()
            output = process.communicate(timeout=60)[0]
            pytest.fail(f"JupyterLab did not serve within {LAB_START_S} s (uid {os.getuid()}):\n{output[-1500:]}")
        assert answer[0] == 200 and "started" in answer[1]
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGTERM)
            try:
                process.wait(timeout=60)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()
    assert process.returncode is not None


@pytest.fixture(scope="module")
def student_site(request):
    from test_browser import _missing_browser

    reason = _missing_browser()
    if reason is not None:
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(f"CI must run the browser test, but {reason}")
        pytest.skip(reason)
    root, _ = request.getfixturevalue("course_release")
    index = build_site(root, student=True)
    return index.parent


def test_the_student_book_shows_no_solution_and_serves_the_release(student_site, tmp_path):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.by import By

    from amdo_lab.course.environment import find_browser
    from test_browser import CHROMIUM_FLAGS

    chapter = find_chapter(0)
    source = nbformat.read(chapter.path, as_version=4)
    solution_lines = [line.strip() for cell in source.cells if SOLUTION_TAG in tags(cell)
                      for line in cell.source.splitlines() if len(line.strip()) > 40]
    found = find_browser()
    options = webdriver.ChromeOptions()
    options.binary_location = found.binary
    for flag in CHROMIUM_FLAGS:
        options.add_argument(flag)
    options.add_argument(f"--user-data-dir={tmp_path / 'profile'}")
    driver = webdriver.Chrome(options=options, service=Service(executable_path=found.driver))
    try:
        driver.get((student_site / f"{chapter.slug}.html").as_uri())
        text = driver.find_element(By.TAG_NAME, "body").get_attribute("textContent")
        folded = driver.find_elements(By.CSS_SELECTOR, ".amdo-solution, .tag_amdo-solution")
        headings = [element.get_attribute("textContent").strip(" #\n\u00b6")
                    for element in driver.find_elements(By.CSS_SELECTOR, "h1, h2, h3")]
    finally:
        driver.quit()
    assert "Exercise 4" in text and "Umeyama" in text
    assert not folded and "Solutions" not in headings and "Rubric (why" not in text
    assert "HIDDEN TESTS" not in text and "EXERCISES.expect" not in text
    shown = [line for line in solution_lines if line in text]
    assert not shown, f"solution text in the student book: {shown[:3]}"
    download = nbformat.read(student_site / "_sources" / chapter.notebook, as_version=4)
    assert not any(SOLUTION_TAG in tags(cell) for cell in download.cells)
    assert not re.search(r"HIDDEN TESTS|EXERCISES\.expect|solution_\d", nbformat.writes(download))
