int TestCameraRayModel(int, char*[])
{
  return 1;
}
