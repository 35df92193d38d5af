""""Did you mean ...?": the nearest known spelling of a mistyped word (difflib).

Called only when something is already wrong (an unknown key, mnemonic, command or
keyword), so its cost never touches a clean run.
"""

from __future__ import annotations

from collections.abc import Iterable


def closest(word: str, known: Iterable[str], cutoff: float = 0.6) -> str | None:
    """The known word nearest to `word` (case-insensitive), or None when none is near."""
    import difflib  # only when something is already wrong

    by_upper: dict[str, str] = {}
    for k in known:
        by_upper.setdefault(k.upper(), k)
    found = difflib.get_close_matches(word.upper(), list(by_upper), n=1, cutoff=cutoff)
    return by_upper[found[0]] if found else None


def did_you_mean(word: str, known: Iterable[str], quote: str = "", cutoff: float = 0.6) -> str:
    """'; did you mean X?' (X quoted with `quote`), or '' when nothing is near."""
    hit = closest(word, known, cutoff)
    return f"; did you mean {quote}{hit}{quote}?" if hit else ""
