"""The page's panels, one class per tab or section of the control panel (see `ui.page`)."""
