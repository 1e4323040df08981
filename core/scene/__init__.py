"""The 3D view's geometry: what a program's run looks like in the scene, as plain numpy data.

Pure functions, no viser and no server: the meshes of the tools, the chuck and the turned part
(`meshes`, `turned`), the camera's preset views (`camera`) and the scene payload a worker builds from a
run (`payload`). server/viz.py only hands these arrays to viser; units are mm, scene axes Z up.
"""
