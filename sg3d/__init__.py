"""sg3d: 3-D scene graphs from posed RGB-D sequences, kept in a graph database."""
__version__ = "0.1.0"
