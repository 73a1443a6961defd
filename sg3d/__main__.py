from sg3d.cli import main

main()
