"""Block kinds: what a kind of block (four-sided, O/C body) hands the trainer: its parameter
space, the base map that builds its boundary in, its start, its loss terms and its guard."""
