"""Weather files of a site: the EnergyPlus EPW reader (:mod:`.epw`) the daylight criterion uses."""
