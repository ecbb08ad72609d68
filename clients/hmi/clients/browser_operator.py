"""An operator in a real browser (headless Debian chromium through
chromedriver and selenium) on the operator page of a running rig.

    browser_operator.py URL UPM_EXE PREFIX USER PASSWORD [SCREENSHOT.png]

Loads the page and reads what it shows beside `upm status --json`; tries a
wrong password; logs in, presses stop and waits for the page to show the
rig stopped; prints one JSON object. Judging is the caller's.
"""

import json
import subprocess
import sys
import time
import urllib.request

from selenium import webdriver
from selenium.webdriver.common.by import By

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"


def text(driver, id_):
    return driver.find_element(By.ID, id_).text.strip()


def wait_for(what, check, timeout_s):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            value = check()
        except Exception:  # the element may be re-drawn under us
            value = None
        if value:
            return value
        time.sleep(0.1)
    raise SystemExit(f"browser_operator: timed out after {timeout_s} s waiting for {what}")


def status(upm, prefix):
    out = subprocess.run([upm, "status", "--json", "--prefix", prefix], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def page_values(driver):
    return {
        "state": text(driver, "state"),
        "parts_on_plate": int(text(driver, "parts-on-plate")),
        "picked": int(text(driver, "picked")),
        "parts_per_minute": float(text(driver, "parts-per-minute")),
    }


def main():
    url, upm, prefix, user, password = sys.argv[1:6]
    screenshot = sys.argv[6] if len(sys.argv) > 6 else None
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for arg in ["--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1400,820"]:
        options.add_argument(arg)
    driver = webdriver.Chrome(options=options, service=webdriver.ChromeService(executable_path=CHROMEDRIVER))
    result = {}
    try:
        driver.get(url)
        result["title"] = driver.title
        # Live: a state and a part count from the WebSocket; a few parts in.
        wait_for("the page's first live values", lambda: text(driver, "parts-on-plate").isdigit(), 30)
        wait_for("three parts on the plate", lambda: int(text(driver, "parts-on-plate")) >= 3, 90)
        before = page_values(driver)
        rig = status(upm, prefix)
        after = page_values(driver)
        result["page_before"], result["page_after"] = before, after
        result["status_state"] = rig["state"]
        result["status_parts_on_plate"] = (rig.get("feed") or {}).get("on_plate")
        result["parts_drawn"] = len(driver.find_elements(By.CSS_SELECTOR, "#plate text"))
        if screenshot:
            time.sleep(2)  # trails
            driver.save_screenshot(screenshot)
        result["stop_enabled_before_login"] = driver.find_element(By.ID, "stop").is_enabled()

        # A wrong password is refused.
        driver.find_element(By.ID, "user").send_keys(user)
        driver.find_element(By.ID, "password").send_keys(password + "-wrong")
        driver.find_element(By.ID, "login").click()
        result["wrong_password"] = wait_for(
            "the wrong password's answer", lambda: text(driver, "login-message").startswith("login refused") and text(driver, "login-message"), 30
        )
        result["stop_enabled_after_wrong_password"] = driver.find_element(By.ID, "stop").is_enabled()

        # The right one; then stop, and the rig stops.
        driver.find_element(By.ID, "user").clear()
        driver.find_element(By.ID, "user").send_keys(user)
        driver.find_element(By.ID, "password").send_keys(password)
        driver.find_element(By.ID, "login").click()
        wait_for("the login", lambda: driver.find_element(By.ID, "stop").is_enabled(), 30)
        result["operator"] = text(driver, "operator-name")
        driver.find_element(By.ID, "stop").click()
        result["page_state_after_stop"] = wait_for(
            "the page to show the rig stopped", lambda: text(driver, "state") == "idle" and "idle", 15
        )
        result["control_message"] = text(driver, "control-message")
        result["status_state_after_stop"] = status(upm, prefix)["state"]
        with urllib.request.urlopen(url.rstrip("/") + "/api/status", timeout=10) as r:
            result["server_status"] = json.load(r)
    finally:
        driver.quit()
    print(json.dumps(result))


if __name__ == "__main__":
    main()
