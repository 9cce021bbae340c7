"""The embodied agent: its body, and the action language it reads and writes."""
