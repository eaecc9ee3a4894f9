"""Sensors: the chain framework (:mod:`.chain`, :mod:`.parts`, :mod:`.structure`) and one
package per sensor kind, each with its equations and its chain: :mod:`.radar`, :mod:`.lidar`,
:mod:`.sonar`, :mod:`.radiometer`, :mod:`.infrared`, :mod:`.ultrasonic`.

The registry of sensor kinds is :data:`diffsense.scene.CHAINS`.
"""
