"""Argument types shared by the command-line modules (argparse ``type=`` callables)."""
from __future__ import annotations

import argparse
import math


def positive_float(text: str) -> float:
    """A positive finite number, or an argparse error naming the problem."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive finite number, got {text}")
    return value


def finite_float(text: str) -> float:
    """A finite number, or an argparse error naming the problem."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text}")
    return value
