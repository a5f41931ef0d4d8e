# SPDX-License-Identifier: BSD-3-Clause
"""Grabs the whole X screen (the ParaView window under Xvfb) once it has stopped changing.

Started by gui_chain.py inside the GUI, as a separate process: the GUI's own screenshot call
captures views only, and a thread inside the GUI would wait for a Python lock the GUI holds.
Usage: grab_window.py OUTPUT.png [DELAY_SECONDS [TIMEOUT_SECONDS]]: waits DELAY (ParaView starts
its test events about a second after the script; they resize a dock), then the screen counts as
settled after three identical grabs 0.5 s apart.
Writes OUTPUT.png, or OUTPUT.png.error with the reason.
"""
import sys
import time


def main(output, delay, timeout):
    from PIL import ImageChops, ImageGrab

    deadline = time.monotonic() + timeout
    time.sleep(delay)
    previous, same = None, 0
    while time.monotonic() < deadline:
        time.sleep(0.5)
        image = ImageGrab.grab(xdisplay=None)  # the display of $DISPLAY
        # A blank screen (before the window maps) does not count as settled.
        settled = previous is not None and ImageChops.difference(image, previous).getbbox() is None
        same = same + 1 if settled and image.getextrema() != ((0, 0), (0, 0), (0, 0)) else 0
        previous = image
        if same >= 2:
            image.save(output)
            return
    raise RuntimeError("the screen did not settle within %g s" % timeout)


if __name__ == "__main__":
    try:
        main(sys.argv[1], float(sys.argv[2]) if len(sys.argv) > 2 else 0.0,
             float(sys.argv[3]) if len(sys.argv) > 3 else 30.0)
    except Exception as error:  # the GUI test looks for this file
        with open(sys.argv[1] + ".error", "w") as stream:
            stream.write("grab_window.py: %s\n" % error)
        sys.exit(1)
