"""Pictures of a stored scene graph, drawn with standard libraries from the application layer's
data (`sg3d.app.scene.fetch_scene`): a top-down node-link diagram (networkx + matplotlib: PNG, SVG,
PDF), an interactive offline 3-D view (plotly, one self-contained HTML file) and the evaluation
report. Pictures are not queries: nothing here reads the store."""
