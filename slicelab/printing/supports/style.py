"""What a support style is: its name, how it shapes the support regions, its help.

See Also
--------
slicelab.printing.supports : the registry.
"""
from __future__ import annotations

from dataclasses import dataclass

__all__ = ["SupportStyle"]


@dataclass(frozen=True)
class SupportStyle:
    """A support style.

    Attributes
    ----------
    name : str
        The name `PrintSettings.support_style` gives.
    close : float
        Gaps narrower than this (mm) between a layer's support regions are filled
        (`slicelab.printing.supports.columns.support_masks`).
    help : str
        One line for ``--help`` and the documentation.

    Examples
    --------
    >>> from slicelab.printing.supports import SUPPORTS
    >>> SUPPORTS["grid"].close > SUPPORTS["snug"].close
    True
    """

    name: str
    close: float
    help: str
