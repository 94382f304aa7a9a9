"""Multi-block domains (SPEC 10): linework, blocks, cell counts, nodes, the multi-block
Winslow solver and the orchestration of a run."""
