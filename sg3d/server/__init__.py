"""Long-running front ends over the application layer: the HTTP API (`sg3d serve`) and the MCP
server (`sg3d mcp`). They translate requests into `app` calls and results into responses."""
