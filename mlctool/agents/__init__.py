"""mlctool for AI agents: `mlc mcp` (docs/agents.md).

Belongs here: the library's functions as tools, plain functions returning plain data
(tools.py), and the MCP server that offers them (mcp_server.py). Does not belong here: what
the tools do (checking, building, simulating, debugging are the stages' own).
"""
