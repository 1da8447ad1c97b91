"""Controllers behind one interface (see ``mimic.agents.base.Agent``)."""
