"""The web UI (`pico-studio serve`): the only package that imports viser.

`runtime.Studio` (no viser) runs source -> perceptor -> behaviour and keeps the timeline;
`scene_data` turns a frame into map-frame geometry per layer; `app.StudioApp` is the viser
page (layers, panels, camera, tools) over a Studio.
"""
