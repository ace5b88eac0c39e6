"""``--help`` is plain text: no reStructuredText literals, roles or table rules."""

from __future__ import annotations

import re

import pytest

from softcath.cli.help_text import plain
from tests.cli.test_options import LEAVES


@pytest.mark.parametrize("key", sorted(LEAVES, key=str), ids=lambda k: " ".join(filter(None, k)))
def test_every_help_is_plain_text(key):
    text = LEAVES[key].format_help()
    assert "``" not in text
    assert not re.search(r":(func|class|mod|meth|attr|data|doc|ref):`", text)
    assert not re.search(r"(?m)^\s*={3,}(\s+={3,})*\s*$", text)


def test_plain_keeps_the_words():
    assert plain("see :func:`softcath.analytic.response` and ``--out DIR``") == (
        "see softcath.analytic.response and --out DIR"
    )
    assert plain("=====  ===\n``paper``  the formula\n=====  ===") == "paper  the formula"
