"""What the scripts share: the checkout, ../shared beside it, and the release build."""

import glob
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared")


def release_mapc():
    """The release build: target/<target>/release/mapc (.cargo/config.toml names the
    machine's own target), else target/release/mapc."""
    found = sorted(glob.glob(os.path.join(ROOT, "target", "*", "release", "mapc")))
    return found[0] if found else os.path.join(ROOT, "target/release/mapc")
