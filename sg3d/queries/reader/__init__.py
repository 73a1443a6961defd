"""The question reader: people's phrasing -> the plain text the grammar reads (`tidy`, over the
rule table sg3d/queries/data/rephrase_rules.toml), typos (`typos`), and the grammar that reads
the text into a logical form."""
