"""The merge of a local graph into the stored graph, without the store (paper Sec. V-C): pairing
scores (`similarity`), the update rules (`update`), the plan of one merge (`plan`), contradiction-free
relations (`consistency`), the re-scan rules (`rescan`), room alignment (`align`), histogram packing
(`histograms`). Plain data in, plain data out; `sg3d.graphdb` reads what a plan needs and applies it."""
