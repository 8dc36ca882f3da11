"""Small pieces of JavaScript the page runs in one tab: the on-canvas legend.

viser 1.1.1 has no public call to run JavaScript in a tab; its own Plotly support sends a
`RunJavascriptMessage` (the client evaluates `source`). That one private call is kept here.
"""

from __future__ import annotations

import json

import viser
from viser import _messages

from pico_studio.ui import style


def run_js(client: viser.ClientHandle, source: str) -> None:
    client._websock_connection.queue_message(_messages.RunJavascriptMessage(source=source))


def show_legend(client: viser.ClientHandle, html: str, visible: bool, dark: bool = False) -> None:
    """The short legend, bottom left over the canvas (clicks go through it)."""
    bg = "rgba(30,30,30,0.85)" if dark else "rgba(255,255,255,0.88)"
    fg = "#eee" if dark else "#222"
    css = (f"position:fixed;left:8px;bottom:8px;z-index:5;background:{bg};color:{fg};padding:4px 8px;"
           f"font:11px sans-serif;line-height:1.45;border-radius:4px;pointer-events:none;"
           f"max-width:{style.LEGEND_BOX[0]}px;max-height:{style.LEGEND_BOX[1]}px;overflow:hidden;"
           f"display:{'block' if visible else 'none'}")
    run_js(client, (
        "(function(){var d=document.getElementById('pico-legend');"
        "if(!d){d=document.createElement('div');d.id='pico-legend';document.body.appendChild(d);}"
        f"d.style.cssText={json.dumps(css)};d.innerHTML={json.dumps(html)};}})();"
    ))
