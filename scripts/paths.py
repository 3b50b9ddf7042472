"""What the scripts share: the checkout, ../shared beside it, and the release build."""

import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared")


def release_mapc():
    """The release build: target/release/mapc."""
    return os.path.join(ROOT, "target/release/mapc")
