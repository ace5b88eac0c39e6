"""The inputs column: one box per design field, grouped as the design file, each with its message.

Numbers are ``FloatInput`` boxes (applied on Enter or when the box loses
focus), choices are ``Select`` boxes. Beside each is a line that shows the
validator's message while the typed value is refused (``.field-error``).
Every box carries the CSS class ``field-<path with dashes>`` (e.g.
``field-tube-h``) so a test or a user style can find it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from softcath.design.io import to_dict
from softcath.studies.app.fields import Field, field_value
from softcath.studies.app.state import AppState

__all__ = ["Inputs", "css_class"]


def css_class(path: str) -> str:
    """The CSS class of the input of ``path`` (``tube.h`` -> ``field-tube-h``)."""
    return "field-" + path.replace(".", "-").replace("_", "-")


def _shown(value: Any) -> Any:
    """A number as the box shows it (6 significant digits), a choice as is."""
    if isinstance(value, float) and math.isfinite(value):
        return float(f"{value:.6g}")
    return value


class Inputs:
    """The input boxes of a design and their messages; ``on_change(path, value)`` on every edit.

    Parameters
    ----------
    state
        The starting state (its fields and values).
    on_change
        Called with the dotted path and the new value when the user edits a box.
    """

    def __init__(self, state: AppState, on_change: Callable[[str, Any], None]) -> None:
        import panel as pn  # heavy (Bokeh, Tornado): imported only when an app is built

        self._on_change = on_change
        self._syncing = False
        self.widgets: dict[str, Any] = {}
        self.messages: dict[str, Any] = {}
        groups: dict[str, list] = {}
        for f in state.fields:
            widget = self._widget(pn, f, field_value(state.design, f.path, state.base_table))
            widget.param.watch(lambda event, path=f.path: self._edited(path, event.new), "value")
            message = pn.pane.HTML(
                "",
                css_classes=["field-error"],
                styles={"color": "#b00020", "font-size": "12px"},
                margin=(0, 10),
            )
            self.widgets[f.path], self.messages[f.path] = widget, message
            groups.setdefault(f.group, []).extend([widget, message])
        self.cards = [
            pn.Card(
                *items, title=f"[{group}]", collapsed=group.startswith("materials.") or group == "assembly"
            )
            for group, items in groups.items()
        ]

    @staticmethod
    def _widget(pn, f: Field, value: Any):
        css = [css_class(f.path)]
        if f.is_choice:
            return pn.widgets.Select(label=f.label, options=list(f.choices), value=value, css_classes=css)
        return pn.widgets.FloatInput(
            label=f"{f.label} [{f.unit}]", value=_shown(value), css_classes=css, width=230
        )

    def _edited(self, path: str, value: Any) -> None:
        if not self._syncing:
            self._on_change(path, value)

    def show(self, state: AppState) -> None:
        """Show ``state``: messages of refused values, the design's values in every other box."""
        self._syncing = True
        try:
            table = None
            for path, widget in self.widgets.items():
                msg = state.errors.get(path, "")
                self.messages[path].object = msg
                if msg:
                    continue  # the refused value stays in its box, next to its message
                if table is None:
                    table = to_dict(state.design)
                value = _shown(field_value(state.design, path, table))
                if value is not None and widget.value != value:
                    widget.value = value
        finally:
            self._syncing = False
